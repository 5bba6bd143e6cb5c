// Quantize (float32 -> int8) and Dequantize (int8 -> float32), per-tensor.
#include <cstdint>

#include "reference/kernels.h"
#include "reference/requantize.h"

namespace tlvlink::reference {
namespace {

// real / scale, rounded half to even, + zero point, saturated (quant_math.h). XNNPACK
// multiplies by the reciprocal scale, which can differ by 1 LSB exactly at rounding ties.
void quantize(const OpArgs& a) {
  const Int8Params q = int8_params(*a.out);
  const float* x = a.input<float>(0);
  int8_t* y = a.output<int8_t>();
  const size_t n = a.out->shape.elements();
  for (size_t i = 0; i < n; ++i) y[i] = quantize_value(x[i], q.scale, q.zero_point);
}

void dequantize(const OpArgs& a) {
  const Int8Params q = int8_params(*a.in[0]);
  const int8_t* x = a.input<int8_t>(0);
  float* y = a.output<float>();
  const size_t n = a.out->shape.elements();
  for (size_t i = 0; i < n; ++i) y[i] = dequantize_value(x[i], q.scale, q.zero_point);
}

}  // namespace

Kernel select_convert(const OpArgs& a) {
  if (a.op->type == OpType::kQuantize && a.in[0]->dtype == DType::kFloat32) return quantize;
  if (a.op->type == OpType::kDequantize && a.out->dtype == DType::kFloat32) return dequantize;
  return nullptr;
}

}  // namespace tlvlink::reference
