// Conv2D, NHWC input, OHWI weights [Cout, KH, KW, Cin/groups]: grouped and depthwise
// (groups == Cin), strides, dilation, explicit padding. Padded taps are skipped, which equals
// padding with the input zero point (they contribute 0 to the centred int8 sum).
#include <cstdint>

#include "reference/kernels.h"
#include "reference/linear_output.h"

namespace tlvlink::reference {
namespace {

// Output channel oc of group g = oc / cout_per_group reads input channels
// [g * cin_per_group, (g + 1) * cin_per_group); for depthwise this is channel oc / multiplier.
template <typename T, typename Acc, typename Output>
void conv_nhwc(const OpArgs& a, Acc x_zero, const Output& output) {
  const Conv2DParams& p = a.op->get<Conv2DParams>();
  const Shape& is = a.in[0]->shape;
  const Shape& os = a.out->shape;
  const int32_t in_h = is[1], in_w = is[2], cin = is[3];
  const int32_t out_h = os[1], out_w = os[2], cout = os[3];
  const int32_t cin_g = cin / p.groups, cout_g = cout / p.groups;
  const T* x = a.input<T>(0);
  const T* w = a.input<T>(1);
  const Acc* bias = a.in[2] != nullptr ? a.input<Acc>(2) : nullptr;
  auto* y = a.output<decltype(output(Acc{}, 0))>();

  size_t o = 0;
  for (int32_t n = 0; n < os[0]; ++n) {
    for (int32_t oy = 0; oy < out_h; ++oy) {
      for (int32_t ox = 0; ox < out_w; ++ox) {
        for (int32_t oc = 0; oc < cout; ++oc) {
          const int32_t first_ic = (oc / cout_g) * cin_g;
          Acc acc = bias != nullptr ? bias[oc] : Acc{0};
          for (int32_t ky = 0; ky < p.kernel_h; ++ky) {
            const int32_t iy = oy * p.stride_h - p.pad_top + ky * p.dilation_h;
            if (iy < 0 || iy >= in_h) continue;
            for (int32_t kx = 0; kx < p.kernel_w; ++kx) {
              const int32_t ix = ox * p.stride_w - p.pad_left + kx * p.dilation_w;
              if (ix < 0 || ix >= in_w) continue;
              const T* xr = x + ((static_cast<size_t>(n) * in_h + iy) * in_w + ix) * cin + first_ic;
              const T* wr =
                  w + ((static_cast<size_t>(oc) * p.kernel_h + ky) * p.kernel_w + kx) * cin_g;
              for (int32_t ic = 0; ic < cin_g; ++ic) {
                acc += (static_cast<Acc>(xr[ic]) - x_zero) * static_cast<Acc>(wr[ic]);
              }
            }
          }
          y[o++] = output(acc, oc);
        }
      }
    }
  }
}

void conv_f32(const OpArgs& a) {
  conv_nhwc<float, float>(a, 0.0f, FloatOutput(a.op->get<Conv2DParams>().activation));
}

void conv_qs8(const OpArgs& a) {
  // Weights are symmetric (zero point 0): checked when the executor is created.
  conv_nhwc<int8_t, int32_t>(
      a, a.in[0]->quant.zero_point[0],
      Int8Output(*a.in[0], *a.in[1], *a.out, a.op->get<Conv2DParams>().activation));
}

}  // namespace

Kernel select_conv2d(const OpArgs& a) {
  switch (a.in[0]->dtype) {
    case DType::kFloat32: return conv_f32;
    case DType::kInt8: return conv_qs8;
    default: return nullptr;
  }
}

}  // namespace tlvlink::reference
