#pragma once
// What calibration records about one float activation tensor, in bounded memory: global
// min/max, a moving average of the per-frame min/max, a count of exact zeros and a histogram.
// Every calibration method (calibration_method.h) derives its range from these, so one
// calibration pass serves all methods (the sweep compares them without re-running frames).
//
//   TensorObserver obs;
//   for (frame : frames) TLV_TRY(obs.observe(values_of_tensor_in(frame), "conv1"));
//   Range r = choose_range(obs, {.method = CalibrationMethod::kPercentile});

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::quantize {

// Bins over [-R, R] (2048 per sign: TensorRT's entropy calibrator uses 2048 over |x|).
inline constexpr int32_t kHistogramBins = 4096;
// R starts at the smallest power of two >= max|x| of the first frame, never below this.
inline constexpr double kMinHistogramRange = 0x1p-24;

// A histogram over [-R, R] whose range R is a power of two that doubles when a value exceeds
// it; doubling merges neighbouring bins exactly (edges stay aligned, 0 is always a bin edge), so
// counts never move between bins approximately. Resolution: at least kHistogramBins / 4 bins
// cover max|x|. Memory: kHistogramBins counters, whatever the number of values.
class Histogram {
 public:
  Histogram();
  // Values must be finite (TensorObserver checks before calling).
  void add(std::span<const float> values);
  // The same when the caller already knows max|values| (it must be exact).
  void add(std::span<const float> values, float max_abs);

  double range() const { return range_; }  // R
  double bin_width() const { return 2.0 * range_ / kHistogramBins; }
  double bin_lower(int32_t bin) const { return -range_ + bin * bin_width(); }
  double bin_center(int32_t bin) const { return bin_lower(bin) + 0.5 * bin_width(); }
  std::span<const uint64_t> counts() const { return counts_; }
  uint64_t total() const { return total_; }

  // The value below which a fraction q in [0, 1] of the values lie, interpolated linearly
  // inside a bin. 0 for an empty histogram.
  double quantile(double q) const;

 private:
  void grow_to(double max_abs);
  std::vector<uint64_t> counts_;
  double range_ = 0;  // 0: nothing added yet
  uint64_t total_ = 0;
};

struct TensorObserver {
  // Weight of the newest frame in the moving average of per-frame min/max (PyTorch's
  // MovingAverageMinMaxObserver default).
  static constexpr double kDefaultAveragingConstant = 0.01;

  float min = std::numeric_limits<float>::infinity();
  float max = -std::numeric_limits<float>::infinity();
  double ema_min = 0, ema_max = 0;  // valid once frames > 0
  uint64_t frames = 0;
  uint64_t zeros = 0;  // values exactly 0 (ReLU outputs), exactly representable
  Histogram histogram;

  bool observed() const { return frames > 0; }

  // One frame's values of the tensor. NaN/Inf is an error naming `tensor` (an activation that
  // overflows float would otherwise become a silent NaN embedding).
  Status observe(std::span<const float> values, std::string_view tensor,
                 double averaging_constant = kDefaultAveragingConstant);
};

}  // namespace tlvlink::quantize
