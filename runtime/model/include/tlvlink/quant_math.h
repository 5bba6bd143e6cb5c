#pragma once
// Scalar int8 quantization arithmetic shared by the reference executor, the quantizer and the
// tools. Rounding is round-half-to-even (what XNNPACK's fp32 requantization does via lrintf);
// implementations that round half away from zero differ by at most 1 LSB.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace tlvlink {

inline constexpr int32_t kInt8Min = -128;
inline constexpr int32_t kInt8Max = 127;
inline constexpr int32_t kWeightMin = -127;  // weights never use -128 (Cortex-A72 smlal pairing)
// Smallest requantization multiplier a fixed-point implementation keeps non-zero.
inline constexpr double kMinRequantMultiplier = 0x1p-31;
// XNNPACK rejects conv/FC whose input_scale * weight_scale / output_scale is not below this.
inline constexpr double kMaxRequantMultiplier = 256.0;

inline int32_t round_half_even(float x) { return static_cast<int32_t>(std::nearbyint(x)); }

inline int8_t saturate_int8(int32_t q, int32_t lo = kInt8Min, int32_t hi = kInt8Max) {
  return static_cast<int8_t>(std::clamp(q, lo, hi));
}

// real -> int8. Non-finite inputs are rejected before this is called; NaN still maps to the
// zero point here so that a missed check cannot become undefined float->int behaviour.
inline int8_t quantize_value(float real, float scale, int32_t zero_point) {
  const float scaled = real / scale;
  if (std::isnan(scaled)) return saturate_int8(zero_point);
  // Clamp in float first so huge values do not overflow the int conversion.
  const float bounded = std::clamp(scaled, -1.0e6f, 1.0e6f);
  return saturate_int8(round_half_even(bounded) + zero_point);
}

inline float dequantize_value(int32_t q, float scale, int32_t zero_point) {
  return static_cast<float>(q - zero_point) * scale;
}

// Quantized bounds of a real-valued clamp range [lo, hi] on an int8 tensor.
inline int32_t quantized_min(float lo, float scale, int32_t zero_point) {
  if (!(lo > -std::numeric_limits<float>::infinity())) return kInt8Min;
  return std::clamp(round_half_even(std::clamp(lo / scale, -1.0e6f, 1.0e6f)) + zero_point, kInt8Min,
                    kInt8Max);
}
inline int32_t quantized_max(float hi, float scale, int32_t zero_point) {
  if (!(hi < std::numeric_limits<float>::infinity())) return kInt8Max;
  return std::clamp(round_half_even(std::clamp(hi / scale, -1.0e6f, 1.0e6f)) + zero_point, kInt8Min,
                    kInt8Max);
}

}  // namespace tlvlink
