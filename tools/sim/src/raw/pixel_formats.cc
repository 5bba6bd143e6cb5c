#include "raw/pixel_formats.h"

#include <algorithm>

namespace tlvlink::sim::internal {
namespace {

// Raw pixel (u, v) is upright pixel origin + u step_u + v step_v (in pixels). Transposed
// layouts (DIGIT): upright = flip_top_bottom(transpose(raw)), so raw (u, v) is upright
// (x = v, y = raw_width - 1 - u).
struct RawWalk {
  ptrdiff_t origin = 0, step_u = 1, step_v = 0;
};

RawWalk raw_walk(const RawLayout& l) {
  const UprightSize up = upright_size(l);
  if (!l.transposed) return {0, 1, up.width};
  return {static_cast<ptrdiff_t>(l.width - 1) * up.width, -static_cast<ptrdiff_t>(up.width), 1};
}

// BT.601: Kr 0.299, Kb 0.114; limited range scales luma by 219/255 and chroma by 224/255.
constexpr float kKr = 0.299f, kKb = 0.114f, kKg = 1 - kKr - kKb;
constexpr float kYScale = 219.0f / 255.0f, kCScale = 224.0f / 255.0f;
constexpr float kCbScale = kCScale / (2 * (1 - kKb)), kCrScale = kCScale / (2 * (1 - kKr));

inline uint8_t clamp_u8(float v) {
  v += 0.5f;
  v = v > 0.0f ? v : 0.0f;
  v = v < 255.0f ? v : 255.0f;
  return static_cast<uint8_t>(v);
}

inline float luma(const uint8_t* p) {
  return kKr * p[0] + kKg * p[1] + kKb * p[2];
}

}  // namespace

// Loops walk pixel indices, not pointers: a transposed walk steps backwards past the start.
void upright_to_raw_rgb(const uint8_t* upright, const RawLayout& l, uint8_t* raw) {
  const RawWalk w = raw_walk(l);
  for (int32_t v = 0; v < l.height; ++v) {
    ptrdiff_t at = w.origin + v * w.step_v;
    uint8_t* out = raw + static_cast<size_t>(v) * static_cast<size_t>(l.width) * 3;
    for (int32_t u = 0; u < l.width; ++u, at += w.step_u, out += 3) {
      std::copy_n(upright + at * 3, 3, out);
    }
  }
}

void raw_rgb_to_upright(const uint8_t* raw, const RawLayout& l, uint8_t* upright) {
  const RawWalk w = raw_walk(l);
  for (int32_t v = 0; v < l.height; ++v) {
    ptrdiff_t at = w.origin + v * w.step_v;
    const uint8_t* in = raw + static_cast<size_t>(v) * static_cast<size_t>(l.width) * 3;
    for (int32_t u = 0; u < l.width; ++u, at += w.step_u, in += 3) {
      std::copy_n(in, 3, upright + at * 3);
    }
  }
}

void upright_to_yuyv(const uint8_t* upright, const RawLayout& l, uint8_t* yuyv) {
  const RawWalk w = raw_walk(l);
  for (int32_t v = 0; v < l.height; ++v) {
    ptrdiff_t at = w.origin + v * w.step_v;
    uint8_t* out = yuyv + static_cast<size_t>(v) * static_cast<size_t>(l.width) * 2;
    for (int32_t u = 0; u < l.width; u += 2, at += 2 * w.step_u, out += 4) {
      const uint8_t* p0 = upright + at * 3;
      const uint8_t* p1 = upright + (at + w.step_u) * 3;
      const float y0 = luma(p0), y1 = luma(p1);
      // The pair's chroma from its mean colour (a 2-tap box, as the camera's 4:2:2 filter).
      const float ym = 0.5f * (y0 + y1);
      const float bm = 0.5f * (static_cast<float>(p0[2]) + static_cast<float>(p1[2]));
      const float rm = 0.5f * (static_cast<float>(p0[0]) + static_cast<float>(p1[0]));
      out[0] = clamp_u8(16 + kYScale * y0);
      out[1] = clamp_u8(128 + kCbScale * (bm - ym));
      out[2] = clamp_u8(16 + kYScale * y1);
      out[3] = clamp_u8(128 + kCrScale * (rm - ym));
    }
  }
}

void yuyv_to_upright(const uint8_t* yuyv, const RawLayout& l, uint8_t* upright) {
  // The inverse matrix: Y' = (Y - 16) / kYScale, B = Y' + Cb / kCbScale, R = Y' + Cr / kCrScale,
  // G = (Y' - Kr R - Kb B) / Kg.
  constexpr float kRCr = 1 / kCrScale;       // 1.596
  constexpr float kBCb = 1 / kCbScale;       // 2.017
  constexpr float kGCb = -kKb / kKg * kBCb;  // -0.392
  constexpr float kGCr = -kKr / kKg * kRCr;  // -0.813
  const RawWalk w = raw_walk(l);
  for (int32_t v = 0; v < l.height; ++v) {
    ptrdiff_t at = w.origin + v * w.step_v;
    const uint8_t* in = yuyv + static_cast<size_t>(v) * static_cast<size_t>(l.width) * 2;
    for (int32_t u = 0; u < l.width; u += 2, in += 4) {
      const float cb = static_cast<float>(in[1]) - 128, cr = static_cast<float>(in[3]) - 128;
      const float dr = kRCr * cr, dg = kGCb * cb + kGCr * cr, db = kBCb * cb;
      for (int k = 0; k < 2; ++k, at += w.step_u) {
        const float y = (static_cast<float>(in[2 * k]) - 16) / kYScale;
        uint8_t* p = upright + at * 3;
        p[0] = clamp_u8(y + dr);
        p[1] = clamp_u8(y + dg);
        p[2] = clamp_u8(y + db);
      }
    }
  }
}

}  // namespace tlvlink::sim::internal
