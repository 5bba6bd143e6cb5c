#pragma once
// The moments of a grasp and the fingers that observe it, as datasets record them and as a grasp
// head's feature layout names them ("A.before,A.during,B.before,B.during").

#include <cstdint>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::heads {

enum class Moment : uint8_t { kBefore = 0, kDuring = 1, kAfter = 2 };
inline constexpr int32_t kFingers = 2;  // gelsightA, gelsightB (a parallel gripper's two fingers)
inline constexpr int32_t kMoments = 3;

const char* moment_name(Moment moment);  // "before", "during", "after"

// One embedding a grasp head reads: a finger (0 = A, 1 = B) at a moment.
struct GraspFeature {
  int32_t finger = 0;
  Moment moment = Moment::kBefore;
};

// A feature layout as (finger, moment) pairs. Fingers "A"/"B" or "finger0"/"finger1"; moments
// "before"/"during"/"after"; comma-separated, spaces allowed. Errors name the bad token
// (kModelInvalidMetadata: the layout comes from a model file). Allocates (setup only).
Result<std::vector<GraspFeature>> parse_grasp_layout(std::string_view layout);

}  // namespace tlvlink::heads
