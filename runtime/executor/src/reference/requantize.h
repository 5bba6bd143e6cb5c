#pragma once
#ifndef TLVLINK_EXECUTOR_PRIVATE
#error \
    "requantize.h is internal to runtime/executor: include the public tlvlink/... headers instead"
#endif
// int8 output stages shared by the quantized kernels. They follow XNNPACK's fp32
// requantization: scale the integer result in float, clamp to the (activation) bounds relative
// to the zero point, round half to even, add the zero point. Clamping before rounding gives the
// same result as after (the bounds are integers) and keeps the float->int conversion in range.

#include <algorithm>
#include <cstdint>

#include "tlvlink/graph.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::reference {

// Quantized output bounds [min, max] of an int8 tensor under a fused activation.
struct Int8Range {
  int32_t min = kInt8Min;
  int32_t max = kInt8Max;
};

inline Int8Range activation_range(Activation activation, const Tensor& out) {
  const float scale = out.quant.scale[0];
  const int32_t zero_point = out.quant.zero_point[0];
  return {quantized_min(activation_min(activation), scale, zero_point),
          quantized_max(activation_max(activation), scale, zero_point)};
}

// `scaled` is the result in units of the output scale, before the zero point is added.
inline int8_t requantize(float scaled, int32_t zero_point, Int8Range range) {
  const float lo = static_cast<float>(range.min - zero_point);
  const float hi = static_cast<float>(range.max - zero_point);
  return static_cast<int8_t>(round_half_even(std::clamp(scaled, lo, hi)) + zero_point);
}

// Per-tensor quantization of an int8 activation (validated: exactly one scale / zero point).
struct Int8Params {
  float scale;
  int32_t zero_point;
};
inline Int8Params int8_params(const Tensor& t) { return {t.quant.scale[0], t.quant.zero_point[0]}; }

}  // namespace tlvlink::reference
