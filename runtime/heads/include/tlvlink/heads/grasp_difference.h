#pragma once
// How much a finger's gel image changed from "before" (open gel) to "during" (the grip settled):
// the grasp head's "A.difference" / "B.difference" features. The encoder's embedding of one
// frame keeps what is in contact but loses how deeply the gel is pressed, which is the grip
// force that decides a grasp (firmware/models/README.md, "What the head still lacks").
//
// Both frames are the model's input (crop and resize of its InputSpec) in DN, 0..255 per channel
// (`difference_input_spec` turns the model's spec into that). With d = during - before per value
// and b = |G * d| (d blurred per channel by a Gaussian, sigma 1.2 px, 9 taps, mirrored edges:
// the blur averages out the sensor's pixel noise, which raw |d| counts as change):
//   0  mean |d|            1  mean d^2
//   2..4  fraction of values with |d| > 5.5, 15.5, 30.5 DN   (8-bit frames give d in 1/3 DN
//         steps after the resize: a threshold between steps does not flip on float rounding)
//   5  mean b              6..9  fraction of values with b > 3, 8, 15, 30 DN
//   10..12  mean d per channel (signed; the model's channel order)
//   13..15  mean b per channel
// Each statistic s is reported as sign(s) * log1p(|s|): mean d^2 spans four decades between a
// light touch and a firm grip, and a linear head reads the logarithm far better.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/metadata.h"

namespace tlvlink::heads {

inline constexpr int32_t kDifferenceFeatures = 16;

// The model's input spec with mean 0 and std 1/255: preprocessing it yields the model's crop and
// resize in DN. The spans point to static storage.
InputSpec difference_input_spec(const InputSpec& model_input);

class GraspDifference {
 public:
  // Images of height x width x channels (DN, interleaved); channels must be 3 (the per-channel
  // statistics), kModelUnsupported otherwise. Allocates its scratch once.
  static Result<GraspDifference> create(int32_t height, int32_t width, int32_t channels);

  size_t values() const { return values_; }  // height * width * channels
  // The 16 features of `during` against `before` into out. No allocation. kShapeMismatch for
  // sizes other than values() (out: kDifferenceFeatures), kNonFiniteValue naming the first
  // NaN/Inf and its index.
  Status compute(std::span<const float> before, std::span<const float> during,
                 std::span<float> out);

 private:
  int32_t height_ = 0, width_ = 0;
  size_t values_ = 0;
  std::vector<float> d_, blurred_;  // d, then the blur's row pass, then b
  // The blur's mirrored source of each tap: column offsets (x * taps + t, in values) and rows.
  std::vector<int32_t> tap_columns_, tap_rows_;
};

}  // namespace tlvlink::heads
