// Grasp feature layouts and the grasp head logit of an episode (runtime arithmetic).

#include <cmath>
#include <string>

#include "tlvlink/eval/heads.h"
#include "tlvlink/heads/grasp_layout.h"
#include "tlvlink/heads/head_math.h"

namespace tlvlink::eval {
const char* grasp_features_name(GraspFeatures f) {
  return f == GraspFeatures::kBeforeAfter ? "before-after" : "before-during";
}

Result<GraspFeatures> parse_grasp_features(std::string_view name) {
  if (name == "before-during") return GraspFeatures::kBeforeDuring;
  if (name == "before-after") return GraspFeatures::kBeforeAfter;
  return Error::make(ErrorCode::kInvalidArgument,
                     "grasp features '%.*s': expected before-during or before-after",
                     static_cast<int>(name.size()), name.data());
}

std::string grasp_feature_layout(GraspFeatures f) {
  return f == GraspFeatures::kBeforeAfter ? "A.before,A.after,B.before,B.after"
                                          : "A.before,A.during,B.before,B.during";
}

Result<float> grasp_head_logit(std::span<const float> weight, float bias,
                               std::string_view feature_layout, const GraspEmbeddings& set,
                               size_t episode) {
  TLV_ASSIGN_OR_RETURN(const auto layout, heads::parse_grasp_layout(feature_layout));
  const size_t d = static_cast<size_t>(set.dim);
  TLV_ENSURE(weight.size() == layout.size() * d, ErrorCode::kShapeMismatch,
             "grasp head has %zu weights; layout '%.*s' with embedding dim %zu needs %zu",
             weight.size(), static_cast<int>(feature_layout.size()), feature_layout.data(), d,
             layout.size() * d);
  std::span<const float> features[heads::kFingers * heads::kMoments];
  TLV_ENSURE(layout.size() <= std::size(features), ErrorCode::kModelInvalidMetadata,
             "grasp layout of %zu features (at most %d)", layout.size(),
             heads::kFingers * heads::kMoments);
  for (size_t k = 0; k < layout.size(); ++k) {
    features[k] = set.frame(episode, layout[k].finger, layout[k].moment);
  }
  return heads::grasp_logit(weight, bias, std::span(features, layout.size()));
}

}  // namespace tlvlink::eval
