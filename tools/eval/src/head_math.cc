// Grasp feature layouts and the grasp head logit of an episode (runtime arithmetic).

#include <cmath>
#include <string>

#include "tlvlink/eval/heads.h"
#include "tlvlink/heads/grasp_layout.h"
#include "tlvlink/heads/head_math.h"

namespace tlvlink::eval {
const char* grasp_features_name(GraspFeatures f) {
  switch (f) {
    case GraspFeatures::kBeforeDuring: return "before-during";
    case GraspFeatures::kBeforeAfter: return "before-after";
    case GraspFeatures::kBeforeDuringDifference: return "before-during-difference";
  }
  return "?";
}

Result<GraspFeatures> parse_grasp_features(std::string_view name) {
  for (GraspFeatures f : {GraspFeatures::kBeforeDuring, GraspFeatures::kBeforeAfter,
                          GraspFeatures::kBeforeDuringDifference}) {
    if (name == grasp_features_name(f)) return f;
  }
  return Error::make(ErrorCode::kInvalidArgument,
                     "grasp features '%.*s': expected before-during-difference, before-during "
                     "or before-after",
                     static_cast<int>(name.size()), name.data());
}

std::string grasp_feature_layout(GraspFeatures f) {
  switch (f) {
    case GraspFeatures::kBeforeAfter: return "A.before,A.after,B.before,B.after";
    case GraspFeatures::kBeforeDuringDifference:
      return "A.before,A.during,A.difference,B.before,B.during,B.difference";
    case GraspFeatures::kBeforeDuring: break;
  }
  return "A.before,A.during,B.before,B.during";
}

Result<float> grasp_head_logit(std::span<const float> weight, float bias,
                               std::string_view feature_layout, const GraspEmbeddings& set,
                               size_t episode) {
  TLV_ASSIGN_OR_RETURN(const auto layout, heads::parse_grasp_layout(feature_layout));
  const size_t needs = heads::layout_values(layout, set.dim);
  TLV_ENSURE(weight.size() == needs, ErrorCode::kShapeMismatch,
             "grasp head has %zu weights; layout '%.*s' with embedding dim %d needs %zu",
             weight.size(), static_cast<int>(feature_layout.size()), feature_layout.data(), set.dim,
             needs);
  TLV_ENSURE(!heads::has_difference(layout) || !set.difference.empty(), ErrorCode::kShapeMismatch,
             "grasp layout '%.*s' reads difference features; the set has none (the model's input "
             "is not 3-channel)",
             static_cast<int>(feature_layout.size()), feature_layout.data());
  std::span<const float> features[heads::kFingers * (heads::kMoments + 1)];
  TLV_ENSURE(layout.size() <= std::size(features), ErrorCode::kModelInvalidMetadata,
             "grasp layout of %zu features (at most %zu)", layout.size(), std::size(features));
  for (size_t k = 0; k < layout.size(); ++k) features[k] = set.feature(episode, layout[k]);
  return heads::grasp_logit(weight, bias, std::span(features, layout.size()));
}

}  // namespace tlvlink::eval
