// ResizeBilinear, NHWC; output height and width come from the output tensor.
// align_corners = false: half-pixel centres, src = (dst + 0.5) * in / out - 0.5, clamped at 0
// (XNNPACK's default). align_corners = true: src = dst * (in - 1) / (out - 1).
// The source coordinate's floor and floor + 1 (clamped to the last pixel) are blended as
// top + (bottom - top) * dy with top/bottom = left + (right - left) * dx. int8 keeps its input's
// quantization (validated), so the blend runs on the int8 values in float and is rounded half
// to even; XNNPACK's int8 kernel uses 11-bit fixed-point weights instead (within 1 LSB).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "reference/kernels.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::reference {
namespace {

// Source sample for one output coordinate along one axis.
struct Tap {
  int32_t lo, hi;  // neighbouring source pixels
  float frac;      // weight of hi
};

Tap source_tap(int32_t dst, int32_t in_size, int32_t out_size, bool align_corners) {
  float src;
  if (align_corners) {
    const float scale =
        out_size > 1 ? static_cast<float>(in_size - 1) / static_cast<float>(out_size - 1) : 0.0f;
    src = static_cast<float>(dst) * scale;
  } else {
    const float scale = static_cast<float>(in_size) / static_cast<float>(out_size);
    src = std::max((static_cast<float>(dst) + 0.5f) * scale - 0.5f, 0.0f);
  }
  const int32_t lo = std::min(static_cast<int32_t>(std::floor(src)), in_size - 1);
  return {lo, std::min(lo + 1, in_size - 1), src - static_cast<float>(lo)};
}

float lerp(float a, float b, float t) { return a + (b - a) * t; }

float to_output(float v, float) { return v; }
int8_t to_output(float v, int8_t) { return static_cast<int8_t>(round_half_even(v)); }

template <typename T>
void resize_bilinear(const OpArgs& a) {
  const bool align = a.op->get<ResizeBilinearParams>().align_corners;
  const Shape& is = a.in[0]->shape;
  const Shape& os = a.out->shape;
  const int32_t in_h = is[1], in_w = is[2], channels = is[3];
  const T* x = a.input<T>(0);
  T* y = a.output<T>();
  size_t o = 0;
  for (int32_t n = 0; n < os[0]; ++n) {
    const T* plane = x + static_cast<size_t>(n) * in_h * in_w * channels;
    for (int32_t oy = 0; oy < os[1]; ++oy) {
      const Tap ty = source_tap(oy, in_h, os[1], align);
      for (int32_t ox = 0; ox < os[2]; ++ox) {
        const Tap tx = source_tap(ox, in_w, os[2], align);
        auto pixel = [&](int32_t iy, int32_t ix) {
          return plane + (static_cast<size_t>(iy) * in_w + ix) * channels;
        };
        const T* tl = pixel(ty.lo, tx.lo);
        const T* tr = pixel(ty.lo, tx.hi);
        const T* bl = pixel(ty.hi, tx.lo);
        const T* br = pixel(ty.hi, tx.hi);
        for (int32_t c = 0; c < channels; ++c) {
          const float top = lerp(static_cast<float>(tl[c]), static_cast<float>(tr[c]), tx.frac);
          const float bottom = lerp(static_cast<float>(bl[c]), static_cast<float>(br[c]), tx.frac);
          y[o++] = to_output(lerp(top, bottom, ty.frac), T{});
        }
      }
    }
  }
}

}  // namespace

Kernel select_resize_bilinear(const OpArgs& a) {
  switch (a.in[0]->dtype) {
    case DType::kFloat32: return resize_bilinear<float>;
    case DType::kInt8: return resize_bilinear<int8_t>;
    default: return nullptr;
  }
}

}  // namespace tlvlink::reference
