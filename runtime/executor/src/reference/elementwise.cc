// Element-wise ops: Add and Mul (numpy broadcasting, fused activation), Clamp, Sigmoid.
// int8 Add/Mul follow XNNPACK's formulas in float (see requantize.h for the output stage):
//   Add: y = round((s_a/s_y)(a - zp_a) + (s_b/s_y)(b - zp_b)) + zp_y
//   Mul: y = round((s_a*s_b/s_y) * (a - zp_a)(b - zp_b)) + zp_y   (integer product, exact)
// int8 Sigmoid dequantizes, applies the float sigmoid and quantizes to the output's
// (1/256, -128), which is how XNNPACK builds its lookup table.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "reference/broadcast.h"
#include "reference/kernels.h"
#include "reference/requantize.h"

namespace tlvlink::reference {
namespace {

template <typename F>
void binary_f32(const OpArgs& a, F f) {
  const Activation act = a.op->get<BinaryParams>().activation;
  const float lo = activation_min(act), hi = activation_max(act);
  const float* x = a.input<float>(0);
  const float* z = a.input<float>(1);
  float* y = a.output<float>();
  for_each_broadcast(
      make_broadcast(a.in[0]->shape, a.in[1]->shape, a.out->shape),
      [&](size_t o, size_t i, size_t j) { y[o] = std::min(std::max(f(x[i], z[j]), lo), hi); });
}

void add_f32(const OpArgs& a) {
  binary_f32(a, [](float p, float q) { return p + q; });
}
void mul_f32(const OpArgs& a) {
  binary_f32(a, [](float p, float q) { return p * q; });
}

// f maps the centred inputs (a - zp_a, b - zp_b) to the result in output-scale units.
template <typename F>
void binary_qs8(const OpArgs& a, F f) {
  const Int8Params pa = int8_params(*a.in[0]), pb = int8_params(*a.in[1]);
  const int32_t zp_y = a.out->quant.zero_point[0];
  const Int8Range range = activation_range(a.op->get<BinaryParams>().activation, *a.out);
  const int8_t* x = a.input<int8_t>(0);
  const int8_t* z = a.input<int8_t>(1);
  int8_t* y = a.output<int8_t>();
  for_each_broadcast(make_broadcast(a.in[0]->shape, a.in[1]->shape, a.out->shape),
                     [&](size_t o, size_t i, size_t j) {
                       y[o] =
                           requantize(f(x[i] - pa.zero_point, z[j] - pb.zero_point), zp_y, range);
                     });
}

void add_qs8(const OpArgs& a) {
  const float s_y = a.out->quant.scale[0];
  const float ra = a.in[0]->quant.scale[0] / s_y;
  const float rb = a.in[1]->quant.scale[0] / s_y;
  binary_qs8(a, [=](int32_t p, int32_t q) {
    return ra * static_cast<float>(p) + rb * static_cast<float>(q);
  });
}

void mul_qs8(const OpArgs& a) {
  const float r = a.in[0]->quant.scale[0] * a.in[1]->quant.scale[0] / a.out->quant.scale[0];
  binary_qs8(a, [=](int32_t p, int32_t q) { return static_cast<float>(p * q) * r; });
}

void clamp_f32(const OpArgs& a) {
  const ClampParams& p = a.op->get<ClampParams>();
  const float* x = a.input<float>(0);
  float* y = a.output<float>();
  const size_t n = a.out->shape.elements();
  for (size_t i = 0; i < n; ++i) y[i] = std::min(std::max(x[i], p.min), p.max);
}

// Clamp keeps its input's quantization (validated), so it clamps the int8 values directly.
void clamp_qs8(const OpArgs& a) {
  const ClampParams& p = a.op->get<ClampParams>();
  const Int8Params q = int8_params(*a.out);
  const int32_t lo = quantized_min(p.min, q.scale, q.zero_point);
  const int32_t hi = quantized_max(p.max, q.scale, q.zero_point);
  const int8_t* x = a.input<int8_t>(0);
  int8_t* y = a.output<int8_t>();
  const size_t n = a.out->shape.elements();
  for (size_t i = 0; i < n; ++i) y[i] = saturate_int8(x[i], lo, hi);
}

float sigmoid(float x) { return 1.0f / (1.0f + std::exp(-x)); }

void sigmoid_f32(const OpArgs& a) {
  const float* x = a.input<float>(0);
  float* y = a.output<float>();
  const size_t n = a.out->shape.elements();
  for (size_t i = 0; i < n; ++i) y[i] = sigmoid(x[i]);
}

void sigmoid_qs8(const OpArgs& a) {
  const Int8Params in = int8_params(*a.in[0]), out = int8_params(*a.out);
  const int8_t* x = a.input<int8_t>(0);
  int8_t* y = a.output<int8_t>();
  const size_t n = a.out->shape.elements();
  for (size_t i = 0; i < n; ++i) {
    y[i] = quantize_value(sigmoid(dequantize_value(x[i], in.scale, in.zero_point)), out.scale,
                          out.zero_point);
  }
}

}  // namespace

Kernel select_elementwise(const OpArgs& a) {
  const bool f32 = a.in[0]->dtype == DType::kFloat32;
  const bool qs8 = a.in[0]->dtype == DType::kInt8;
  if (!f32 && !qs8) return nullptr;
  switch (a.op->type) {
    case OpType::kAdd: return f32 ? add_f32 : add_qs8;
    case OpType::kMul: return f32 ? mul_f32 : mul_qs8;
    case OpType::kClamp: return f32 ? clamp_f32 : clamp_qs8;
    case OpType::kSigmoid: return f32 ? sigmoid_f32 : sigmoid_qs8;
    default: return nullptr;
  }
}

}  // namespace tlvlink::reference
