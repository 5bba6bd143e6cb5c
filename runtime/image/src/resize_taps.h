#pragma once
#ifndef TLVLINK_IMAGE_PRIVATE
#error "resize_taps.h is internal to runtime/image: include tlvlink/image/preprocess.h instead"
#endif
// The resize arithmetic of the preprocessing, shared by the plan and the resize convenience so
// both compute every pixel the same way.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "tlvlink/image/image.h"
#include "tlvlink/image/preprocess.h"

namespace tlvlink::image::detail {

// Bilinear with half-pixel centres: output index o of out_len reads the source axis of in_len
// at f = clamp((o + 0.5) * in/out - 0.5, 0, in - 1), between floor(f) and the next pixel.
inline ResizeTap bilinear_tap(int32_t in_len, int32_t out_len, int32_t o, int32_t offset) {
  const float s = static_cast<float>(in_len) / static_cast<float>(out_len);
  const float f =
      std::clamp((static_cast<float>(o) + 0.5f) * s - 0.5f, 0.0f, static_cast<float>(in_len - 1));
  const auto a = static_cast<int32_t>(f);
  return {offset + a, offset + std::min(a + 1, in_len - 1), f - static_cast<float>(a)};
}

// Rows r, columns c: interpolate along x, then y; round half away from zero into uint8.
inline uint8_t bilinear_value(const ImageView& f, const ResizeTap& r, const ResizeTap& c,
                              int32_t k) {
  const float top =
      f.at(r.i0, c.i0, k) + c.w * static_cast<float>(f.at(r.i0, c.i1, k) - f.at(r.i0, c.i0, k));
  const float bot =
      f.at(r.i1, c.i0, k) + c.w * static_cast<float>(f.at(r.i1, c.i1, k) - f.at(r.i1, c.i0, k));
  return static_cast<uint8_t>(std::lround(std::clamp(top + r.w * (bot - top), 0.0f, 255.0f)));
}

// Box filter: the mean of the source pixels in [r.i0, r.i1) x [c.i0, c.i1), rounded.
inline uint8_t area_value(const ImageView& f, const ResizeTap& r, const ResizeTap& c, int32_t k) {
  uint32_t sum = 0;
  for (int32_t sy = r.i0; sy < r.i1; ++sy)
    for (int32_t sx = c.i0; sx < c.i1; ++sx) sum += f.at(sy, sx, k);
  const auto n = static_cast<uint32_t>((r.i1 - r.i0) * (c.i1 - c.i0));
  return static_cast<uint8_t>((sum + n / 2) / n);
}

}  // namespace tlvlink::image::detail
