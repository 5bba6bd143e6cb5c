// FullyConnected: input [N, Cin], weights [Cout, Cin], optional bias [Cout], output [N, Cout].
#include <cstdint>

#include "reference/kernels.h"
#include "reference/linear_output.h"

namespace tlvlink::reference {
namespace {

template <typename T, typename Acc, typename Output>
void fully_connected(const OpArgs& a, Acc x_zero, const Output& output) {
  const int32_t batch = a.in[0]->shape[0], cin = a.in[0]->shape[1], cout = a.out->shape[1];
  const T* x = a.input<T>(0);
  const T* w = a.input<T>(1);
  const Acc* bias = a.in[2] != nullptr ? a.input<Acc>(2) : nullptr;
  auto* y = a.output<decltype(output(Acc{}, 0))>();
  for (int32_t n = 0; n < batch; ++n) {
    const T* xr = x + static_cast<size_t>(n) * cin;
    for (int32_t oc = 0; oc < cout; ++oc) {
      const T* wr = w + static_cast<size_t>(oc) * cin;
      Acc acc = bias != nullptr ? bias[oc] : Acc{0};
      for (int32_t i = 0; i < cin; ++i) {
        acc += (static_cast<Acc>(xr[i]) - x_zero) * static_cast<Acc>(wr[i]);
      }
      y[static_cast<size_t>(n) * cout + oc] = output(acc, oc);
    }
  }
}

void fc_f32(const OpArgs& a) {
  fully_connected<float, float>(a, 0.0f, FloatOutput(a.op->get<FullyConnectedParams>().activation));
}

void fc_qs8(const OpArgs& a) {
  fully_connected<int8_t, int32_t>(
      a, a.in[0]->quant.zero_point[0],
      Int8Output(*a.in[0], *a.in[1], *a.out, a.op->get<FullyConnectedParams>().activation));
}

}  // namespace

Kernel select_fully_connected(const OpArgs& a) {
  switch (a.in[0]->dtype) {
    case DType::kFloat32: return fc_f32;
    case DType::kInt8: return fc_qs8;
    default: return nullptr;
  }
}

}  // namespace tlvlink::reference
