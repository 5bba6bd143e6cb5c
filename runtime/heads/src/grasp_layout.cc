#include "tlvlink/heads/grasp_layout.h"

#include <algorithm>

#include "tlvlink/heads/grasp_difference.h"

namespace tlvlink::heads {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

const char* moment_name(Moment m) {
  switch (m) {
    case Moment::kBefore: return "before";
    case Moment::kDuring: return "during";
    case Moment::kAfter: return "after";
  }
  return "?";
}

int32_t feature_values(const GraspFeature& f, int32_t embedding_dim) {
  return f.kind == FeatureKind::kDifference ? kDifferenceFeatures : embedding_dim;
}

size_t layout_values(std::span<const GraspFeature> layout, int32_t embedding_dim) {
  size_t n = 0;
  for (const GraspFeature& f : layout) n += static_cast<size_t>(feature_values(f, embedding_dim));
  return n;
}

bool reads_frame(std::span<const GraspFeature> layout, int32_t finger, Moment moment) {
  return std::any_of(layout.begin(), layout.end(), [&](const GraspFeature& f) {
    if (f.finger != finger) return false;
    if (f.kind == FeatureKind::kDifference)
      return moment == Moment::kBefore || moment == Moment::kDuring;
    return f.moment == moment;
  });
}

bool has_difference(std::span<const GraspFeature> layout) {
  return std::any_of(layout.begin(), layout.end(),
                     [](const GraspFeature& f) { return f.kind == FeatureKind::kDifference; });
}

Result<std::vector<GraspFeature>> parse_grasp_layout(std::string_view layout) {
  std::vector<GraspFeature> out;
  while (!layout.empty()) {
    const size_t comma = layout.find(',');
    const std::string_view token = trim(layout.substr(0, comma));
    layout = comma == std::string_view::npos ? std::string_view() : layout.substr(comma + 1);
    const size_t dot = token.find('.');
    TLV_ENSURE(dot != std::string_view::npos, ErrorCode::kModelInvalidMetadata,
               "grasp feature '%.*s' is not FINGER.MOMENT or FINGER.difference (e.g. A.before)",
               static_cast<int>(token.size()), token.data());
    const std::string_view finger = token.substr(0, dot), moment = token.substr(dot + 1);
    int32_t f = -1;
    if (finger == "A" || finger == "finger0") f = 0;
    if (finger == "B" || finger == "finger1") f = 1;
    TLV_ENSURE(f >= 0, ErrorCode::kModelInvalidMetadata,
               "grasp feature '%.*s': finger must be A, B, finger0 or finger1",
               static_cast<int>(token.size()), token.data());
    Moment m = Moment::kDuring;
    FeatureKind kind = FeatureKind::kEmbedding;
    if (moment == "difference") {
      kind = FeatureKind::kDifference;
    } else if (moment == "before") {
      m = Moment::kBefore;
    } else if (moment == "during") {
      m = Moment::kDuring;
    } else if (moment == "after") {
      m = Moment::kAfter;
    } else {
      return Error::make(ErrorCode::kModelInvalidMetadata,
                         "grasp feature '%.*s': moment must be before, during, after or difference",
                         static_cast<int>(token.size()), token.data());
    }
    const GraspFeature feature{f, m, kind};
    TLV_ENSURE(std::none_of(out.begin(), out.end(),
                            [&](const GraspFeature& o) {
                              return o.finger == f && o.moment == m && o.kind == kind;
                            }),
               ErrorCode::kModelInvalidMetadata, "grasp feature '%.*s' is named twice",
               static_cast<int>(token.size()), token.data());
    out.push_back(feature);
  }
  TLV_ENSURE(!out.empty(), ErrorCode::kModelInvalidMetadata, "empty grasp feature layout");
  return out;
}

}  // namespace tlvlink::heads
