// Histogram with exact power-of-two range growth, and the per-tensor observer.

#include "tlvlink/quantize/observer.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace tlvlink::quantize {

Histogram::Histogram() : counts_(static_cast<size_t>(kHistogramBins), 0) {}

void Histogram::grow_to(double max_abs) {
  if (range_ == 0) {
    range_ = kMinHistogramRange;
    while (range_ < max_abs) range_ *= 2;
    return;
  }
  constexpr size_t kQuarter = kHistogramBins / 4;
  while (range_ < max_abs) {
    // Bins 2j and 2j+1 of [-R, R] become bin kQuarter + j of [-2R, 2R] (edges coincide).
    std::vector<uint64_t> merged(counts_.size(), 0);
    for (size_t j = 0; j < counts_.size() / 2; ++j)
      merged[kQuarter + j] = counts_[2 * j] + counts_[2 * j + 1];
    counts_.swap(merged);
    range_ *= 2;
  }
}

void Histogram::add(std::span<const float> values) {
  float max_abs = 0;
  for (float v : values) max_abs = std::max(max_abs, std::fabs(v));
  add(values, max_abs);
}

void Histogram::add(std::span<const float> values, float max_abs) {
  if (values.empty()) return;
  grow_to(static_cast<double>(max_abs));
  // bins / (2R) is a power of two, so v * inv_width is exact; |v| <= R keeps the shifted index
  // non-negative, so truncation is floor.
  const double inv_width = 1.0 / bin_width();
  constexpr double kHalf = kHistogramBins / 2;
  constexpr int64_t kLast = kHistogramBins - 1;
  uint64_t* counts = counts_.data();
  for (float v : values) {
    const auto bin = static_cast<int64_t>(static_cast<double>(v) * inv_width + kHalf);
    ++counts[std::min(bin, kLast)];  // x = R lands on the edge past the last bin
  }
  total_ += values.size();
}

double Histogram::quantile(double q) const {
  if (total_ == 0) return 0;
  const double target = std::clamp(q, 0.0, 1.0) * static_cast<double>(total_);
  double below = 0;
  for (int32_t b = 0; b < kHistogramBins; ++b) {
    const auto n = static_cast<double>(counts_[static_cast<size_t>(b)]);
    if (n > 0 && below + n >= target) {
      return bin_lower(b) + bin_width() * std::clamp((target - below) / n, 0.0, 1.0);
    }
    below += n;
  }
  return range_;
}

Status TensorObserver::observe(std::span<const float> values, std::string_view tensor,
                               double averaging_constant) {
  if (values.empty()) return {};
  float lo = values[0], hi = values[0], max_abs = 0;
  uint64_t zero_count = 0;
  bool finite = true;
  for (const float v : values) {
    finite = finite && std::isfinite(v);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    max_abs = std::max(max_abs, std::fabs(v));
    zero_count += v == 0.0f ? 1 : 0;
  }
  if (!finite) {
    for (size_t i = 0; i < values.size(); ++i) {
      if (std::isfinite(values[i])) continue;
      return Error::make(ErrorCode::kNonFiniteValue,
                         "tensor '%.*s' element %zu is %g during calibration: the float model "
                         "overflows (or produces NaN) on this frame",
                         static_cast<int>(tensor.size()), tensor.data(), i,
                         static_cast<double>(values[i]));
    }
  }
  min = std::min(min, lo);
  max = std::max(max, hi);
  if (frames == 0) {
    ema_min = static_cast<double>(lo);
    ema_max = static_cast<double>(hi);
  } else {
    ema_min += averaging_constant * (static_cast<double>(lo) - ema_min);
    ema_max += averaging_constant * (static_cast<double>(hi) - ema_max);
  }
  ++frames;
  zeros += zero_count;
  histogram.add(values, max_abs);
  return {};
}

}  // namespace tlvlink::quantize
