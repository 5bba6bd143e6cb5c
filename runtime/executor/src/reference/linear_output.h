#pragma once
#ifndef TLVLINK_EXECUTOR_PRIVATE
#error \
    "linear_output.h is internal to runtime/executor: include the public tlvlink/... headers instead"
#endif
// Output stages of the dot-product ops (Conv2D, FullyConnected), applied to one accumulator of
// output channel c. fp32 clamps to the fused activation. int8 is XNNPACK's fp32
// requantization: y = clamp(round_half_even(acc * (s_x * s_w[c] / s_y)) + zp_y, qmin, qmax),
// with the multiplier computed in float in that order, as XNNPACK's operator setup does.

#include <algorithm>
#include <cstdint>
#include <span>

#include "reference/requantize.h"
#include "tlvlink/graph.h"

namespace tlvlink::reference {

struct FloatOutput {
  explicit FloatOutput(Activation activation)
      : lo(activation_min(activation)), hi(activation_max(activation)) {}
  float operator()(float acc, int32_t /*channel*/) const { return std::min(std::max(acc, lo), hi); }

  float lo, hi;
};

struct Int8Output {
  Int8Output(const Tensor& input, const Tensor& weights, const Tensor& output,
             Activation activation)
      : input_scale(input.quant.scale[0]),
        output_scale(output.quant.scale[0]),
        weight_scales(weights.quant.scale),
        zero_point(output.quant.zero_point[0]),
        range(activation_range(activation, output)) {}

  int8_t operator()(int32_t acc, int32_t channel) const {
    const size_t c = weight_scales.size() == 1 ? 0 : static_cast<size_t>(channel);
    const float multiplier = input_scale * weight_scales[c] / output_scale;
    return requantize(static_cast<float>(acc) * multiplier, zero_point, range);
  }

  float input_scale, output_scale;
  std::span<const float> weight_scales;  // 1 (per-tensor) or one per output channel
  int32_t zero_point;
  Int8Range range;
};

}  // namespace tlvlink::reference
