// Grasp feature layouts, the grasp head logit and zero-shot logits (runtime order).

#include <cmath>
#include <string>

#include "tlvlink/eval/heads.h"

namespace tlvlink::eval {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

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

Result<std::vector<std::pair<int32_t, sim::Moment>>> parse_grasp_layout(std::string_view layout) {
  std::vector<std::pair<int32_t, sim::Moment>> out;
  while (!layout.empty()) {
    const size_t comma = layout.find(',');
    const std::string_view token = trim(layout.substr(0, comma));
    layout = comma == std::string_view::npos ? std::string_view() : layout.substr(comma + 1);
    const size_t dot = token.find('.');
    TLV_ENSURE(dot != std::string_view::npos, ErrorCode::kModelInvalidMetadata,
               "grasp feature '%.*s' is not FINGER.MOMENT (e.g. A.before)",
               static_cast<int>(token.size()), token.data());
    const std::string_view finger = token.substr(0, dot), moment = token.substr(dot + 1);
    int32_t f = -1;
    if (finger == "A" || finger == "finger0") f = 0;
    if (finger == "B" || finger == "finger1") f = 1;
    TLV_ENSURE(f >= 0, ErrorCode::kModelInvalidMetadata,
               "grasp feature '%.*s': finger must be A, B, finger0 or finger1",
               static_cast<int>(token.size()), token.data());
    sim::Moment m;
    if (moment == "before") {
      m = sim::Moment::kBefore;
    } else if (moment == "during") {
      m = sim::Moment::kDuring;
    } else if (moment == "after") {
      m = sim::Moment::kAfter;
    } else {
      return Error::make(ErrorCode::kModelInvalidMetadata,
                         "grasp feature '%.*s': moment must be before, during or after",
                         static_cast<int>(token.size()), token.data());
    }
    out.emplace_back(f, m);
  }
  TLV_ENSURE(!out.empty(), ErrorCode::kModelInvalidMetadata, "empty grasp feature layout");
  return out;
}

Result<float> grasp_head_logit(std::span<const float> weight, float bias,
                               std::string_view feature_layout, const GraspEmbeddings& set,
                               size_t episode) {
  TLV_ASSIGN_OR_RETURN(const auto layout, parse_grasp_layout(feature_layout));
  const size_t d = static_cast<size_t>(set.dim);
  TLV_ENSURE(weight.size() == layout.size() * d, ErrorCode::kShapeMismatch,
             "grasp head has %zu weights; layout '%.*s' with embedding dim %zu needs %zu",
             weight.size(), static_cast<int>(feature_layout.size()), feature_layout.data(), d,
             layout.size() * d);
  float acc = bias;
  for (size_t k = 0; k < layout.size(); ++k) {
    const std::span<const float> e = set.frame(episode, layout[k].first, layout[k].second);
    for (size_t i = 0; i < d; ++i) acc += weight[k * d + i] * e[i];
  }
  return acc;
}

void zero_shot_logits(std::span<const float> prompt_matrix, float logit_scale,
                      std::span<const float> e, std::span<float> logits) {
  const size_t dim = e.size();
  double norm = 0;
  for (float v : e) norm += static_cast<double>(v) * static_cast<double>(v);
  const auto inv = static_cast<float>(norm > 0 ? 1.0 / std::sqrt(norm) : 0.0);
  for (size_t k = 0; k < logits.size(); ++k) {
    float acc = 0;
    for (size_t i = 0; i < dim; ++i) acc += prompt_matrix[k * dim + i] * e[i] * inv;
    logits[k] = logit_scale * acc;
  }
}

}  // namespace tlvlink::eval
