#include "tlvlink/heads/grasp_layout.h"

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

Result<std::vector<GraspFeature>> parse_grasp_layout(std::string_view layout) {
  std::vector<GraspFeature> out;
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
    Moment m;
    if (moment == "before") {
      m = Moment::kBefore;
    } else if (moment == "during") {
      m = Moment::kDuring;
    } else if (moment == "after") {
      m = Moment::kAfter;
    } else {
      return Error::make(ErrorCode::kModelInvalidMetadata,
                         "grasp feature '%.*s': moment must be before, during or after",
                         static_cast<int>(token.size()), token.data());
    }
    out.push_back({f, m});
  }
  TLV_ENSURE(!out.empty(), ErrorCode::kModelInvalidMetadata, "empty grasp feature layout");
  return out;
}

}  // namespace tlvlink::heads
