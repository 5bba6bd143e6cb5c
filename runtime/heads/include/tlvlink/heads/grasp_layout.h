#pragma once
// The moments of a grasp and the fingers that observe it, as datasets record them and as a grasp
// head's feature layout names them ("A.before,A.during,B.before,B.during", and
// "A.difference": how the finger's image changed from before to during, grasp_difference.h).

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::heads {

enum class Moment : uint8_t { kBefore = 0, kDuring = 1, kAfter = 2 };
inline constexpr int32_t kFingers = 2;  // gelsightA, gelsightB (a parallel gripper's two fingers)
inline constexpr int32_t kMoments = 3;

const char* moment_name(Moment moment);  // "before", "during", "after"

enum class FeatureKind : uint8_t {
  kEmbedding = 0,   // the encoder's embedding of the finger's frame at `moment`
  kDifference = 1,  // kDifferenceFeatures statistics of the finger's during - before images
};

// One feature a grasp head reads: a finger (0 = A, 1 = B) at a moment, or the finger's
// before-to-during difference (moment kDuring: it is known once the "during" frame is).
struct GraspFeature {
  int32_t finger = 0;
  Moment moment = Moment::kBefore;
  FeatureKind kind = FeatureKind::kEmbedding;
};

// Values the feature contributes to the head's input: embedding_dim, or kDifferenceFeatures.
int32_t feature_values(const GraspFeature& feature, int32_t embedding_dim);
// The values of all the layout's features: a grasp head's weight count.
size_t layout_values(std::span<const GraspFeature> layout, int32_t embedding_dim);
// Whether a layout reads this finger's frame at this moment (a difference reads before and
// during).
bool reads_frame(std::span<const GraspFeature> layout, int32_t finger, Moment moment);
bool has_difference(std::span<const GraspFeature> layout);

// A feature layout. Tokens FINGER.MOMENT or FINGER.difference, comma-separated, spaces allowed;
// fingers "A"/"B" or "finger0"/"finger1", moments "before"/"during"/"after". A token given twice
// is an error. Errors name the bad token (kModelInvalidMetadata: the layout comes from a model
// file). Allocates (setup only).
Result<std::vector<GraspFeature>> parse_grasp_layout(std::string_view layout);

}  // namespace tlvlink::heads
