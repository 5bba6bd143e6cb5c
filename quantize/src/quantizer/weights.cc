// Conv/FC weights and bias: symmetric int8 weights (per channel or per tensor), int32 bias at
// s_in * s_w, and the int8 constraints of the loader and XNNPACK, each either met by a stated
// adjustment or reported as the reason the layer stays fp32.

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <string>

#include "quantizer/quantizer_internal.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::quantize::quantizer_internal {

std::string strf(const char* format, ...) {
  char text[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof(text), format, args);
  va_end(args);
  return text;
}

namespace {

// Raises `scale` to `needed` when needed is larger; returns the factor (1 when unchanged).
double raise_to(float& scale, double needed) {
  if (needed <= static_cast<double>(scale)) return 1.0;
  const double factor = needed / static_cast<double>(scale);
  // Round up so the float scale is not below what was needed.
  scale = std::nextafter(static_cast<float>(needed), std::numeric_limits<float>::infinity());
  return factor;
}

}  // namespace

void quantize_symmetric(std::span<const float> values, float scale, std::span<int8_t> out) {
  for (size_t i = 0; i < values.size(); ++i) {
    const float q = std::clamp(values[i] / scale, -1.0e6f, 1.0e6f);
    out[i] = saturate_int8(round_half_even(q), kWeightMin, kInt8Max);
  }
}

double sqnr_db(double signal_energy, double error_energy) {
  if (error_energy <= 0) return std::numeric_limits<double>::infinity();
  if (signal_energy <= 0) return std::numeric_limits<double>::quiet_NaN();
  return 10.0 * std::log10(signal_energy / error_energy);
}

LinearWeights quantize_linear(const LinearRequest& r) {
  LinearWeights out;
  const auto cout = static_cast<size_t>(r.cout);
  const size_t per = r.weights.size() / cout;
  const bool per_channel = r.granularity == WeightGranularity::kPerChannel;
  const size_t nscales = per_channel ? cout : 1;
  const double s_in = static_cast<double>(r.input_scale),
               s_out = static_cast<double>(r.output_scale);

  // 1. Scales from max|w| (floored so a dead channel still has a normal scale).
  out.scales.assign(nscales, 0.0f);
  for (size_t c = 0; c < cout; ++c) {
    float max_abs = 0;
    for (size_t i = 0; i < per; ++i) max_abs = std::max(max_abs, std::fabs(r.weights[c * per + i]));
    float& s = out.scales[per_channel ? c : 0];
    s = std::max(s, std::max(max_abs / static_cast<float>(kInt8Max), kMinWeightScale));
  }

  // 2. Scales the constraints need: the bias must fit in kMaxBiasMagnitude, and the
  //    requantization multiplier must not fall below 2^-31 (a fixed-point multiplier that small
  //    flushes the channel's output to zero; its weights are then negligible anyway).
  for (size_t c = 0; c < cout; ++c) {
    const size_t sc = per_channel ? c : 0;
    float& s = out.scales[sc];
    const std::string channel =
        per_channel ? strf("channel %zu", c) : strf("the per-tensor scale (channel %zu)", c);
    if (!r.bias.empty()) {
      const double b = std::fabs(static_cast<double>(r.bias[c]));
      const double needed = b / (s_in * kMaxBiasMagnitude);
      if (needed > static_cast<double>(s)) {
        const double factor = needed / static_cast<double>(s);
        if (factor > r.max_bias_scale_raise) {
          out.failure =
              channel +
              strf(
                  ": int32 bias %.4g / (s_in * s_w) = %.3g does not fit in 2^30; fitting it would "
                  "raise the weight scale x%.3g (allowed x%g)",
                  b, b / (s_in * static_cast<double>(s)), factor, r.max_bias_scale_raise);
          return out;
        }
        raise_to(s, needed);
        out.adjustments.push_back(
            channel +
            strf(": weight scale raised x%.3g so the int32 bias (%.4g at s_in*s_w) fits in 2^30",
                 factor, b));
      }
    }
    const double multiplier = s_in * static_cast<double>(s) / s_out;
    if (multiplier < kMinRequantMultiplier) {
      const double factor = raise_to(s, kMinRequantMultiplier * (1.0 + 1e-6) * s_out / s_in);
      out.adjustments.push_back(
          channel +
          strf(": requantization multiplier %.3g < 2^-31 (weights move the output by < %.2g LSB); "
               "weight scale raised x%.3g",
               multiplier, multiplier * 255.0 * 127.0 * static_cast<double>(per), factor));
    }
  }

  // 3. Multiplier ceiling, as XNNPACK computes it (float) and as the loader does (double).
  for (size_t sc = 0; sc < nscales; ++sc) {
    const float mf = r.input_scale * out.scales[sc] / r.output_scale;
    const double md = s_in * static_cast<double>(out.scales[sc]) / s_out;
    if (!(mf < static_cast<float>(kMaxRequantMultiplier)) || !(md < kMaxRequantMultiplier)) {
      out.failure = strf(
          "requantization multiplier s_in*s_w/s_out = %.4g >= 256 (scale %zu): the output "
          "range is too narrow for the input and weight scales",
          md, sc);
      return out;
    }
  }

  // 4. Values, bias, accumulator bound, weight-only SQNR.
  out.values.resize(r.weights.size());
  double signal = 0, error = 0;
  for (size_t c = 0; c < cout; ++c) {
    const float s = out.scales[per_channel ? c : 0];
    const std::span<const float> w = r.weights.subspan(c * per, per);
    const std::span<int8_t> q = std::span<int8_t>(out.values).subspan(c * per, per);
    quantize_symmetric(w, s, q);
    int64_t abs_sum = 0;
    for (size_t i = 0; i < per; ++i) {
      abs_sum += std::abs(static_cast<int32_t>(q[i]));
      const double wd = static_cast<double>(w[i]);
      const double e = wd - static_cast<double>(q[i]) * static_cast<double>(s);
      signal += wd * wd;
      error += e * e;
    }
    int64_t abs_bias = 0;
    if (!r.bias.empty()) {
      const double bq =
          std::nearbyint(static_cast<double>(r.bias[c]) / (s_in * static_cast<double>(s)));
      out.bias.push_back(
          static_cast<int32_t>(std::clamp(bq, -kMaxBiasMagnitude, kMaxBiasMagnitude)));
      abs_bias = std::llabs(static_cast<long long>(out.bias.back()));
    }
    const int64_t bound = abs_bias + kMaxCenteredInput * abs_sum;
    if (bound >= kAccumulatorLimit) {
      out.failure = strf(
          "channel %zu: worst-case int32 accumulator |bias| + 255*sum|w| = %lld reaches 2^31 "
          "(K = %zu inputs per output)",
          c, static_cast<long long>(bound), per);
      return out;
    }
  }
  if (!r.bias.empty()) {
    for (float s : out.scales)
      out.bias_scales.push_back(static_cast<float>(s_in * static_cast<double>(s)));
  }
  out.weight_sqnr_db = sqnr_db(signal, error);
  return out;
}

ActivationParams activation_params(const TensorRange& range, float min_range) {
  ActivationParams p;
  if (!range.observed() || !std::isfinite(range.min) || !std::isfinite(range.max)) {
    p.failure = "no finite calibration range";
    return p;
  }
  // Double: hi - lo of two large floats can overflow float (e.g. +-3e38).
  const double lo = std::min(0.0, static_cast<double>(range.min));
  double hi = std::max(0.0, static_cast<double>(range.max));
  if (hi - lo < static_cast<double>(min_range)) hi = lo + static_cast<double>(min_range);
  const double scale = (hi - lo) / 255.0;
  const auto fscale = static_cast<float>(scale);
  if (!std::isfinite(fscale) || !std::isnormal(fscale)) {
    p.failure = strf("range [%.4g, %.4g] has no finite normal int8 scale (%.4g)", lo, hi, scale);
    return p;
  }
  const double zp =
      std::nearbyint(static_cast<double>(kInt8Min) - lo / static_cast<double>(fscale));
  p.spec = QuantSpec::per_tensor(fscale, static_cast<int32_t>(std::clamp(zp, -128.0, 127.0)));
  return p;
}

}  // namespace tlvlink::quantize::quantizer_internal
