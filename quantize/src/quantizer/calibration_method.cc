// Range selection from observer statistics: minmax, ema, percentile, entropy (KL), MSE.

#include "tlvlink/quantize/calibration_method.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace tlvlink::quantize {
namespace {

// KL smoothing: a quantized bin that is empty where the reference is not gets this probability
// (MXNet / TensorRT smooth the same way) so the divergence stays finite but large.
constexpr double kKlSmoothing = 1e-4;

Range clamp_to_observed(const TensorObserver& obs, double lo, double hi) {
  Range r;
  r.lo = static_cast<float>(
      std::clamp(lo, static_cast<double>(obs.min), static_cast<double>(obs.max)));
  r.hi = static_cast<float>(
      std::clamp(hi, static_cast<double>(obs.min), static_cast<double>(obs.max)));
  if (r.lo > r.hi) std::swap(r.lo, r.hi);
  return r;
}

Range observed_range(const TensorObserver& obs) {
  return obs.observed() ? Range{obs.min, obs.max} : Range{};
}

// KL(P || Q) of the candidate that keeps the first `i` bins of `p` and merges them onto
// `levels` quantized levels (TensorRT's entropy calibration).
double candidate_divergence(const std::vector<double>& p, size_t i, size_t levels,
                            std::vector<double>& ref, std::vector<double>& quant) {
  ref.assign(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(i));
  for (size_t b = i; b < p.size(); ++b) ref[i - 1] += p[b];  // clipped mass lands on the rail
  quant.assign(i, 0.0);
  for (size_t j = 0; j < levels; ++j) {
    const size_t start = j * i / levels, stop = (j + 1) * i / levels;
    double total = 0;
    size_t nonzero = 0;
    for (size_t b = start; b < stop; ++b) {
      total += p[b];
      nonzero += p[b] > 0 ? 1 : 0;
    }
    if (nonzero == 0) continue;
    for (size_t b = start; b < stop; ++b)
      quant[b] = p[b] > 0 ? total / static_cast<double>(nonzero) : 0;
  }
  double ref_sum = 0, quant_sum = 0;
  for (size_t b = 0; b < i; ++b) {
    ref_sum += ref[b];
    quant_sum += quant[b];
  }
  if (ref_sum <= 0 || quant_sum <= 0) return std::numeric_limits<double>::infinity();
  double kl = 0;
  for (size_t b = 0; b < i; ++b) {
    if (ref[b] <= 0) continue;
    const double pb = ref[b] / ref_sum;
    const double qb = std::max(quant[b] / quant_sum, kKlSmoothing * pb);
    kl += pb * std::log(pb / qb);
  }
  return kl;
}

}  // namespace

const char* calibration_method_name(CalibrationMethod method) {
  switch (method) {
    case CalibrationMethod::kMinMax: return "minmax";
    case CalibrationMethod::kEma: return "ema";
    case CalibrationMethod::kPercentile: return "percentile";
    case CalibrationMethod::kEntropy: return "entropy";
    case CalibrationMethod::kMse: return "mse";
  }
  return "?";
}

Result<CalibrationMethod> parse_calibration_method(std::string_view name) {
  for (CalibrationMethod m : kAllCalibrationMethods) {
    if (name == calibration_method_name(m)) return m;
  }
  return Error::make(ErrorCode::kInvalidArgument,
                     "unknown calibration method '%.*s' (minmax, ema, percentile, entropy, mse)",
                     static_cast<int>(name.size()), name.data());
}

Status validate(const CalibrationOptions& options) {
  TLV_ENSURE(options.percentile > 50.0 && options.percentile <= 100.0, ErrorCode::kInvalidArgument,
             "percentile %g outside (50, 100]", options.percentile);
  return {};
}

Range percentile_range(const TensorObserver& obs, double percentile) {
  if (!obs.observed()) return {};
  const double tail = (100.0 - percentile) / 100.0;
  return clamp_to_observed(obs, obs.histogram.quantile(tail), obs.histogram.quantile(1.0 - tail));
}

Range entropy_range(const TensorObserver& obs) {
  if (!obs.observed() || (obs.min == 0.0f && obs.max == 0.0f)) return observed_range(obs);
  const std::span<const uint64_t> c = obs.histogram.counts();
  constexpr size_t kHalf = kHistogramBins / 2;
  const bool positive = obs.min >= 0.0f, negative = obs.max <= 0.0f;
  // One distribution over |x| starting at 0: one side, or both folded together.
  std::vector<double> p(kHalf);
  for (size_t k = 0; k < kHalf; ++k) {
    const auto up = static_cast<double>(c[kHalf + k]), down = static_cast<double>(c[kHalf - 1 - k]);
    p[k] = positive ? up : negative ? down : up + down;
  }
  // Exact zeros (ReLU outputs; often most of a tensor) are represented exactly whatever the range;
  // left in, their spike makes every wider candidate look worse and KL clips far too much
  // (NVIDIA's pytorch-quantization flattens the zero bin for the same reason).
  p[0] = std::max(0.0, p[0] - static_cast<double>(obs.zeros));
  size_t used = kHalf;
  while (used > 0 && p[used - 1] == 0) --used;
  const size_t levels =
      static_cast<size_t>(positive || negative ? CalibrationOptions::kEntropyLevelsOneSided
                                               : CalibrationOptions::kEntropyLevelsFolded);
  // Everything already fits in `levels` bins: quantizing the full range loses nothing to clip.
  if (used <= levels) return observed_range(obs);
  std::vector<double> ref, quant;
  size_t best = used;
  double best_kl = std::numeric_limits<double>::infinity();
  for (size_t i = levels; i <= used; ++i) {
    const double kl = candidate_divergence(p, i, levels, ref, quant);
    if (kl < best_kl) {
      best_kl = kl;
      best = i;
    }
  }
  const double t = static_cast<double>(best) * obs.histogram.bin_width();
  return clamp_to_observed(obs, -t, t);
}

namespace {

// Integral of (x - s round(x/s))^2 from -s/2 to x: n whole periods of s^3/12, then the partial
// one (the rounding error is periodic in s and 0 is on the grid).
double rounding_integral(double x, double s) {
  const double n = std::nearbyint(x / s), r = x - n * s;
  return n * s * s * s / 12.0 + (r * r * r + s * s * s / 8.0) / 3.0;
}

// Integral of (x - c)^2 over [a, b].
double squared_distance_integral(double a, double b, double c) {
  return ((b - c) * (b - c) * (b - c) - (a - c) * (a - c) * (a - c)) / 3.0;
}

}  // namespace

double expected_quantization_mse(const TensorObserver& obs, double lo, double hi) {
  const Histogram& h = obs.histogram;
  if (h.total() == 0) return 0;
  const double s = (hi - lo) / 255.0;
  const double w = h.bin_width();
  double total = 0;
  const std::span<const uint64_t> c = h.counts();
  for (int32_t b = 0; b < kHistogramBins; ++b) {
    double n = static_cast<double>(c[static_cast<size_t>(b)]);
    if (b == kHistogramBins / 2) n -= static_cast<double>(obs.zeros);  // exact zeros: no error
    if (n <= 0) continue;
    // Values spread uniformly over the bin; the error integrated exactly over its three parts:
    // clipped to lo, rounded to the grid s*Z inside [lo, hi], clipped to hi.
    const double a = h.bin_lower(b), e = a + w;
    double err = 0;
    if (a < lo) err += squared_distance_integral(a, std::min(e, lo), lo);
    if (e > hi) err += squared_distance_integral(std::max(a, hi), e, hi);
    const double ia = std::max(a, lo), ie = std::min(e, hi);
    if (ie > ia) err += s > 0 ? rounding_integral(ie, s) - rounding_integral(ia, s) : 0.0;
    total += n * err / w;
  }
  return total / static_cast<double>(h.total());
}

Range mse_range(const TensorObserver& obs) {
  if (!obs.observed()) return {};
  const double lo0 = std::min(0.0, static_cast<double>(obs.min));
  const double hi0 = std::max(0.0, static_cast<double>(obs.max));
  if (hi0 - lo0 <= 0) return observed_range(obs);
  constexpr int32_t kCoarse = CalibrationOptions::kMseCoarseSteps;
  constexpr int32_t kFine = CalibrationOptions::kMseFineSteps;
  double lo = lo0, hi = hi0, best = expected_quantization_mse(obs, lo0, hi0);
  // Minimises over f in (0, 1] of make(f) -> (lo, hi): a coarse grid of f, then a fine grid
  // around the best coarse value.
  auto search = [&](auto make) {
    double best_f = -1;
    auto consider = [&](double f) {
      if (f <= 0 || f > 1) return;
      const auto [l, h] = make(f);
      const double e = expected_quantization_mse(obs, l, h);
      if (e < best) {
        best = e;
        best_f = f;
      }
    };
    for (int32_t k = kCoarse; k >= 1; --k) consider(static_cast<double>(k) / kCoarse);
    if (best_f < 0) return;
    const double centre = best_f;
    for (int32_t k = -kFine; k <= kFine; ++k)
      consider(centre + static_cast<double>(k) / (static_cast<double>(kCoarse) * kFine));
    std::tie(lo, hi) = make(best_f);
  };
  // Both ends scaled together, then each end on its own (the two are coupled through the step
  // (hi - lo) / 255), twice: asymmetric tails get their own clip.
  search([&](double f) { return std::pair{f * lo0, f * hi0}; });
  for (int round = 0; round < 2; ++round) {
    const double l = lo, h = hi;
    if (h > 0) search([&](double f) { return std::pair{l, f * hi0}; });
    if (l < 0) search([&, hh = hi](double f) { return std::pair{f * lo0, hh}; });
  }
  return clamp_to_observed(obs, lo, hi);
}

Range choose_range(const TensorObserver& obs, const CalibrationOptions& options) {
  if (!obs.observed()) return {};
  switch (options.method) {
    case CalibrationMethod::kMinMax: return observed_range(obs);
    case CalibrationMethod::kEma:
      return clamp_to_observed(obs, std::min(obs.ema_min, obs.ema_max),
                               std::max(obs.ema_min, obs.ema_max));
    case CalibrationMethod::kPercentile: return percentile_range(obs, options.percentile);
    case CalibrationMethod::kEntropy: return entropy_range(obs);
    case CalibrationMethod::kMse: return mse_range(obs);
  }
  return observed_range(obs);
}

}  // namespace tlvlink::quantize
