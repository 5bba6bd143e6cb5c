#include <algorithm>

#include "tlvlink/image/convert.h"

namespace tlvlink::image {
namespace {

// Camera pixel (u, v) is upright pixel origin + u step_u + v step_v (in pixels). Transposed
// (DIGIT): upright = flip_top_bottom(transpose(camera)), so camera (u, v) is upright
// (x = v, y = camera_width - 1 - u).
struct Walk {
  ptrdiff_t origin = 0, step_u = 1, step_v = 0;
};

Walk walk(int32_t width, int32_t height, Orientation o) {
  const Size up = upright_size(width, height, o);
  if (o == Orientation::kUpright) return {0, 1, up.width};
  return {static_cast<ptrdiff_t>(width - 1) * up.width, -static_cast<ptrdiff_t>(up.width), 1};
}

// BT.601: Kr 0.299, Kb 0.114; limited range scales luma by 219/255 and chroma by 224/255.
constexpr float kKr = 0.299f, kKb = 0.114f, kKg = 1 - kKr - kKb;
constexpr float kYScale = 219.0f / 255.0f, kCScale = 224.0f / 255.0f;
constexpr float kCbScale = kCScale / (2 * (1 - kKb)), kCrScale = kCScale / (2 * (1 - kKr));
// The inverse matrix: Y' = (Y - 16) / kYScale, B = Y' + Cb / kCbScale, R = Y' + Cr / kCrScale,
// G = (Y' - Kr R - Kb B) / Kg.
constexpr float kRCr = 1 / kCrScale;       // 1.596
constexpr float kBCb = 1 / kCbScale;       // 2.017
constexpr float kGCb = -kKb / kKg * kBCb;  // -0.392
constexpr float kGCr = -kKr / kKg * kRCr;  // -0.813

inline uint8_t clamp_u8(float v) {
  v += 0.5f;
  v = v > 0.0f ? v : 0.0f;
  v = v < 255.0f ? v : 255.0f;
  return static_cast<uint8_t>(v);
}

inline float luma(const uint8_t* p) { return kKr * p[0] + kKg * p[1] + kKb * p[2]; }

inline void ycc_to_rgb(uint8_t y8, float dr, float dg, float db, uint8_t* p) {
  const float y = (static_cast<float>(y8) - 16) / kYScale;
  p[0] = clamp_u8(y + dr);
  p[1] = clamp_u8(y + dg);
  p[2] = clamp_u8(y + db);
}

size_t line_bytes(const FrameFormat& f, size_t packed) {
  return f.stride > 0 ? static_cast<size_t>(f.stride) : packed;
}

// Loops walk pixel indices, not pointers: a transposed walk steps backwards past the start.
void yuyv(const uint8_t* in, const FrameFormat& f, const Walk& w, uint8_t* up) {
  const size_t line = line_bytes(f, static_cast<size_t>(f.width) * 2);
  for (int32_t v = 0; v < f.height; ++v) {
    ptrdiff_t at = w.origin + v * w.step_v;
    const uint8_t* p = in + static_cast<size_t>(v) * line;
    for (int32_t u = 0; u < f.width; u += 2, p += 4) {
      const float cb = static_cast<float>(p[1]) - 128, cr = static_cast<float>(p[3]) - 128;
      const float dr = kRCr * cr, dg = kGCb * cb + kGCr * cr, db = kBCb * cb;
      for (int k = 0; k < 2; ++k, at += w.step_u) ycc_to_rgb(p[2 * k], dr, dg, db, up + at * 3);
    }
  }
}

void nv12(const uint8_t* in, const FrameFormat& f, const Walk& w, uint8_t* up) {
  const size_t line = line_bytes(f, static_cast<size_t>(f.width));
  const uint8_t* uv_plane = in + line * static_cast<size_t>(f.height);
  for (int32_t v = 0; v < f.height; ++v) {
    ptrdiff_t at = w.origin + v * w.step_v;
    const uint8_t* y = in + static_cast<size_t>(v) * line;
    const uint8_t* uv = uv_plane + static_cast<size_t>(v / 2) * line;
    for (int32_t u = 0; u < f.width; ++u, at += w.step_u) {
      const size_t c = static_cast<size_t>(u / 2) * 2;
      const float cb = static_cast<float>(uv[c]) - 128, cr = static_cast<float>(uv[c + 1]) - 128;
      ycc_to_rgb(y[u], kRCr * cr, kGCb * cb + kGCr * cr, kBCb * cb, up + at * 3);
    }
  }
}

void rgb_or_grey(const uint8_t* in, const FrameFormat& f, const Walk& w, uint8_t* up) {
  const bool grey = f.format == PixelFormat::kGrey;
  const size_t bpp = grey ? 1 : 3;
  const size_t line = line_bytes(f, static_cast<size_t>(f.width) * bpp);
  for (int32_t v = 0; v < f.height; ++v) {
    ptrdiff_t at = w.origin + v * w.step_v;
    const uint8_t* p = in + static_cast<size_t>(v) * line;
    for (int32_t u = 0; u < f.width; ++u, at += w.step_u, p += bpp) {
      uint8_t* o = up + at * 3;
      if (grey) {
        o[0] = o[1] = o[2] = p[0];
      } else {
        std::copy_n(p, 3, o);
      }
    }
  }
}

}  // namespace

Size upright_size(int32_t width, int32_t height, Orientation o) {
  return o == Orientation::kTransposed ? Size{height, width} : Size{width, height};
}

Status camera_to_upright_rgb(std::span<const uint8_t> frame, const FrameFormat& f, Orientation o,
                             std::span<uint8_t> upright, const char* what) {
  TLV_ENSURE(f.format != PixelFormat::kMjpeg, ErrorCode::kInvalidArgument,
             "%s: MJPEG is decoded by JpegDecoder, not converted", what);
  TLV_ENSURE(f.width >= 1 && f.height >= 1 && (f.format != PixelFormat::kYuyv || f.width % 2 == 0),
             ErrorCode::kFormat, "%s: %s frame of %dx%d", what, pixel_format_name(f.format),
             f.width, f.height);
  const size_t need = frame_bytes(f);
  TLV_ENSURE(frame.size() >= need, ErrorCode::kFormat, "%s: %zu bytes; %dx%d %s is %zu bytes", what,
             frame.size(), f.width, f.height, pixel_format_name(f.format), need);
  TLV_ENSURE(upright.size() == static_cast<size_t>(f.width) * static_cast<size_t>(f.height) * 3,
             ErrorCode::kShapeMismatch, "%s: RGB buffer of %zu bytes for %dx%d", what,
             upright.size(), f.width, f.height);
  const Walk w = walk(f.width, f.height, o);
  switch (f.format) {
    case PixelFormat::kYuyv: yuyv(frame.data(), f, w, upright.data()); break;
    case PixelFormat::kNv12: nv12(frame.data(), f, w, upright.data()); break;
    default: rgb_or_grey(frame.data(), f, w, upright.data()); break;
  }
  return {};
}

Status upright_rgb_to_camera(std::span<const uint8_t> upright, const FrameFormat& f, Orientation o,
                             std::span<uint8_t> frame) {
  const bool yuv = f.format == PixelFormat::kYuyv;
  TLV_ENSURE((yuv && f.width % 2 == 0) || f.format == PixelFormat::kRgb24,
             ErrorCode::kInvalidArgument,
             "simulated cameras emit RGB24 or YUYV (even width), not %s %dx%d",
             pixel_format_name(f.format), f.width, f.height);
  const size_t pixels = static_cast<size_t>(f.width) * static_cast<size_t>(f.height);
  TLV_ENSURE(upright.size() == pixels * 3 && frame.size() == pixels * (yuv ? 2 : 3),
             ErrorCode::kShapeMismatch, "%dx%d %s: buffers of %zu and %zu bytes", f.width, f.height,
             pixel_format_name(f.format), upright.size(), frame.size());
  const Walk w = walk(f.width, f.height, o);
  const uint8_t* up = upright.data();
  for (int32_t v = 0; v < f.height; ++v) {
    ptrdiff_t at = w.origin + v * w.step_v;
    if (!yuv) {
      uint8_t* out = frame.data() + static_cast<size_t>(v) * static_cast<size_t>(f.width) * 3;
      for (int32_t u = 0; u < f.width; ++u, at += w.step_u, out += 3)
        std::copy_n(up + at * 3, 3, out);
      continue;
    }
    uint8_t* out = frame.data() + static_cast<size_t>(v) * static_cast<size_t>(f.width) * 2;
    for (int32_t u = 0; u < f.width; u += 2, at += 2 * w.step_u, out += 4) {
      const uint8_t* p0 = up + at * 3;
      const uint8_t* p1 = up + (at + w.step_u) * 3;
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
  return {};
}

}  // namespace tlvlink::image
