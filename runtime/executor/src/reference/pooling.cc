// GlobalAveragePool [N,H,W,C] -> [N,1,1,C] and MaxPool2D (NHWC).
// int8 average: y = round(sum(x - zp_x) * (s_x / s_y / (H*W))) + zp_y, the sum exact in int32
// and the scale in float, as XNNPACK's global average pooling computes it.
// MaxPool works on int8 values directly (it keeps its input's quantization). Padded positions
// never win: a window coordinate outside the input is clamped to the nearest edge pixel, which
// is what XNNPACK's indirection buffer does and equals "ignore padding" whenever the window
// overlaps the input.
#include <algorithm>
#include <cstdint>

#include "reference/kernels.h"
#include "reference/requantize.h"

namespace tlvlink::reference {
namespace {

struct PlaneDims {
  int32_t n, h, w, c;
};
PlaneDims dims_of(const Shape& s) { return {s[0], s[1], s[2], s[3]}; }

void global_average_pool_f32(const OpArgs& a) {
  const PlaneDims d = dims_of(a.in[0]->shape);
  const float* x = a.input<float>(0);
  float* y = a.output<float>();
  const size_t pixels = static_cast<size_t>(d.h) * d.w;
  const float inv = 1.0f / static_cast<float>(pixels);
  for (int32_t n = 0; n < d.n; ++n) {
    for (int32_t c = 0; c < d.c; ++c) {
      const float* xc = x + static_cast<size_t>(n) * pixels * d.c + c;
      float sum = 0.0f;
      for (size_t i = 0; i < pixels; ++i) sum += xc[i * d.c];
      y[static_cast<size_t>(n) * d.c + c] = sum * inv;
    }
  }
}

void global_average_pool_qs8(const OpArgs& a) {
  const PlaneDims d = dims_of(a.in[0]->shape);
  const Int8Params in = int8_params(*a.in[0]), out = int8_params(*a.out);
  const int8_t* x = a.input<int8_t>(0);
  int8_t* y = a.output<int8_t>();
  const size_t pixels = static_cast<size_t>(d.h) * d.w;
  const float scale = in.scale / out.scale / static_cast<float>(pixels);
  // |x - zp| <= 255, so the int64 sum is exact for any plane the loader accepts.
  for (int32_t n = 0; n < d.n; ++n) {
    for (int32_t c = 0; c < d.c; ++c) {
      const int8_t* xc = x + static_cast<size_t>(n) * pixels * d.c + c;
      int64_t sum = 0;
      for (size_t i = 0; i < pixels; ++i) sum += xc[i * d.c] - in.zero_point;
      y[static_cast<size_t>(n) * d.c + c] =
          requantize(static_cast<float>(sum) * scale, out.zero_point, Int8Range{});
    }
  }
}

template <typename T>
void max_pool(const OpArgs& a) {
  const Pool2DParams& p = a.op->get<Pool2DParams>();
  const PlaneDims in = dims_of(a.in[0]->shape), out = dims_of(a.out->shape);
  const T* x = a.input<T>(0);
  T* y = a.output<T>();
  for (int32_t n = 0; n < out.n; ++n) {
    for (int32_t oy = 0; oy < out.h; ++oy) {
      for (int32_t ox = 0; ox < out.w; ++ox) {
        T* yp = y + ((static_cast<size_t>(n) * out.h + oy) * out.w + ox) * out.c;
        for (int32_t py = 0; py < p.pool_h; ++py) {
          const int32_t iy = std::clamp(oy * p.stride_h - p.pad_top + py, 0, in.h - 1);
          for (int32_t px = 0; px < p.pool_w; ++px) {
            const int32_t ix = std::clamp(ox * p.stride_w - p.pad_left + px, 0, in.w - 1);
            const T* xp = x + ((static_cast<size_t>(n) * in.h + iy) * in.w + ix) * in.c;
            const bool first = py == 0 && px == 0;
            for (int32_t c = 0; c < in.c; ++c) yp[c] = first ? xp[c] : std::max(yp[c], xp[c]);
          }
        }
      }
    }
  }
}

}  // namespace

Kernel select_pooling(const OpArgs& a) {
  const DType dtype = a.in[0]->dtype;
  if (dtype != DType::kFloat32 && dtype != DType::kInt8) return nullptr;
  const bool f32 = dtype == DType::kFloat32;
  switch (a.op->type) {
    case OpType::kGlobalAveragePool: return f32 ? global_average_pool_f32 : global_average_pool_qs8;
    case OpType::kMaxPool2D: return f32 ? max_pool<float> : max_pool<int8_t>;
    default: return nullptr;
  }
}

}  // namespace tlvlink::reference
