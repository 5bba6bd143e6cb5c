#pragma once
// Calibration methods: how an activation's int8 range [lo, hi] is chosen from what a
// TensorObserver recorded. The range is then widened to include 0 and floored
// (activation_quant in calibrate.h).
//
//   minmax      [min, max] over all frames
//   ema         moving average of each frame's min and max (TensorObserver::ema_*)
//   percentile  lower/upper tails of (100 - p) % cut off, from the histogram (p = 99.99 default)
//   entropy     TensorRT's KL-divergence threshold search over the histogram
//   mse         the clipping range minimising the expected squared quantization error over the
//               histogram (values uniform within each bin; rounding to the grid inside the
//               range and distance to the rail outside, both integrated exactly)
//
// Percentile, entropy and MSE clip outliers; minmax and ema never clip observed values.

#include <cstdint>
#include <string_view>

#include "tlvlink/error.h"
#include "tlvlink/quantize/observer.h"

namespace tlvlink::quantize {

enum class CalibrationMethod : uint8_t { kMinMax = 0, kEma, kPercentile, kEntropy, kMse };
inline constexpr CalibrationMethod kAllCalibrationMethods[] = {
    CalibrationMethod::kMinMax, CalibrationMethod::kEma, CalibrationMethod::kPercentile,
    CalibrationMethod::kEntropy, CalibrationMethod::kMse};

const char* calibration_method_name(CalibrationMethod method);  // "minmax", "ema", ...
Result<CalibrationMethod> parse_calibration_method(std::string_view name);

struct CalibrationOptions {
  CalibrationMethod method = CalibrationMethod::kMinMax;
  double percentile = 99.99;  // kPercentile: in (50, 100]
  // kMse: candidate ranges alpha * [min, max] (0 included), then each end alone (two rounds of
  // coordinate descent); alpha on a 1/kMseCoarseSteps grid, refined to
  // 1/(kMseCoarseSteps * kMseFineSteps) around the best coarse value.
  static constexpr int32_t kMseCoarseSteps = 100;
  static constexpr int32_t kMseFineSteps = 20;
  // kEntropy: quantized levels on each candidate range (255 one-sided, 128 per side of a
  // two-sided tensor folded to |x|, as TensorRT does for its symmetric int8).
  static constexpr int32_t kEntropyLevelsOneSided = 255;
  static constexpr int32_t kEntropyLevelsFolded = 128;
};
Status validate(const CalibrationOptions& options);

struct Range {
  float lo = 0, hi = 0;
};

// The range of one observed tensor under `options`. Always finite with lo <= hi and inside
// [obs.min, obs.max]; an unobserved tensor or an all-zero one gives [min, max] (the caller's
// floor then applies).
Range choose_range(const TensorObserver& obs, const CalibrationOptions& options);

// The building blocks, exposed for tests. All take the observer's histogram and its min/max.
Range percentile_range(const TensorObserver& obs, double percentile);
Range entropy_range(const TensorObserver& obs);
Range mse_range(const TensorObserver& obs);

// Expected squared error per value of quantizing the observed distribution to 256 levels on
// [lo, hi] (lo <= 0 <= hi), under the model used by mse_range (exact zeros cost nothing).
double expected_quantization_mse(const TensorObserver& obs, double lo, double hi);

}  // namespace tlvlink::quantize
