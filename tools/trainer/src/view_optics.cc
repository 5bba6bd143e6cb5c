// Image operations of the sensor-view augmentation.

#include "view_optics.h"

#include <algorithm>
#include <cmath>

#include "augment_rng.h"

namespace tlvlink::trainer::view {
namespace {

inline float sample(const float* src, int32_t width, int32_t height, double x, double y,
                    int32_t c) {
  x = std::clamp(x, 0.0, static_cast<double>(width - 1));
  y = std::clamp(y, 0.0, static_cast<double>(height - 1));
  const auto x0 = static_cast<int32_t>(x), y0 = static_cast<int32_t>(y);
  const int32_t x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
  const auto fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const auto at = [&](int32_t yy, int32_t xx) {
    return src[(static_cast<size_t>(yy) * static_cast<size_t>(width) + static_cast<size_t>(xx)) *
                   3 +
               static_cast<size_t>(c)];
  };
  const float top = at(y0, x0) + fx * (at(y0, x1) - at(y0, x0));
  const float bot = at(y1, x0) + fx * (at(y1, x1) - at(y1, x0));
  return top + fy * (bot - top);
}

}  // namespace

void warp(const float* src, float* dst, int32_t width, int32_t height, const Affine& a) {
  const double cx = width / 2.0, cy = height / 2.0;
  const double c = std::cos(a.rotation_rad) / a.scale, s = std::sin(a.rotation_rad) / a.scale;
  size_t i = 0;
  for (int32_t y = 0; y < height; ++y) {
    for (int32_t x = 0; x < width; ++x, i += 3) {
      // The inverse map: where in the unmounted frame this camera pixel's centre looks.
      const double X = x + 0.5 - cx - a.shift_x, Y = y + 0.5 - cy - a.shift_y;
      const double u = cx + c * X + s * Y - 0.5, v = cy - s * X + c * Y - 0.5;
      for (int32_t k = 0; k < 3; ++k)
        dst[i + static_cast<size_t>(k)] = sample(src, width, height, u, v, k);
    }
  }
}

void shade(float* f, int32_t width, int32_t height, const Shading& s) {
  const double half_diag2 = (width * width + height * height) / 4.0;
  const double vx = s.vignette_cx * width, vy = s.vignette_cy * height;
  const double dx = std::cos(s.drift_angle_rad), dy = std::sin(s.drift_angle_rad);
  // t spans [-1, 1] over the frame along the drift direction.
  const double reach = std::abs(dx) * width / 2.0 + std::abs(dy) * height / 2.0;
  size_t i = 0;
  for (int32_t y = 0; y < height; ++y) {
    for (int32_t x = 0; x < width; ++x, i += 3) {
      const double px = x + 0.5, py = y + 0.5;
      const double r2 = ((px - vx) * (px - vx) + (py - vy) * (py - vy)) / half_diag2;
      const auto v = static_cast<float>(1.0 - s.vignette * r2);
      const auto t =
          static_cast<float>(((px - width / 2.0) * dx + (py - height / 2.0) * dy) / reach);
      for (size_t c = 0; c < 3; ++c) {
        f[i + c] = f[i + c] * s.gain[c] * v * (1.0f + s.drift[c] * t) + s.offset[c];
      }
    }
  }
}

void darken(float* f, int32_t width, int32_t height, const Speck& d) {
  const double reach = 3 * d.radius;
  const int32_t x0 = std::max(0, static_cast<int32_t>(std::floor(d.x - reach)));
  const int32_t x1 = std::min(width - 1, static_cast<int32_t>(std::ceil(d.x + reach)));
  const int32_t y0 = std::max(0, static_cast<int32_t>(std::floor(d.y - reach)));
  const int32_t y1 = std::min(height - 1, static_cast<int32_t>(std::ceil(d.y + reach)));
  for (int32_t y = y0; y <= y1; ++y) {
    for (int32_t x = x0; x <= x1; ++x) {
      const double ex = x + 0.5 - d.x, ey = y + 0.5 - d.y;
      const auto k = static_cast<float>(
          1.0 - d.darkness * std::exp(-(ex * ex + ey * ey) / (2 * d.radius * d.radius)));
      float* p =
          f + (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * 3;
      p[0] *= k;
      p[1] *= k;
      p[2] *= k;
    }
  }
}

namespace {

// One 1-D pass of `taps` weights along rows (step 3: neighbouring pixels) or columns (step
// width * 3) of `len` pixels, from `src` to `dst`, edges repeated.
void blur_line(const float* src, float* dst, int32_t len, size_t step, const float* kernel,
               int32_t taps) {
  const int32_t half = taps / 2;
  for (int32_t i = 0; i < len; ++i) {
    float acc[3] = {0, 0, 0};
    const bool inside = i - half >= 0 && i + half < len;
    for (int32_t t = 0; t < taps; ++t) {
      const int32_t j = inside ? i + t - half : std::clamp(i + t - half, 0, len - 1);
      const float* p = src + static_cast<size_t>(j) * step;
      acc[0] += kernel[t] * p[0];
      acc[1] += kernel[t] * p[1];
      acc[2] += kernel[t] * p[2];
    }
    float* d = dst + static_cast<size_t>(i) * step;
    d[0] = acc[0];
    d[1] = acc[1];
    d[2] = acc[2];
  }
}

}  // namespace

void blur(float* f, int32_t width, int32_t height, double sigma, std::vector<float>& tmp) {
  if (sigma <= 0) return;
  float kernel[63];
  const int32_t half = std::min(31, std::max(1, static_cast<int32_t>(std::ceil(2.5 * sigma))));
  const int32_t taps = 2 * half + 1;
  float sum = 0;
  for (int32_t t = 0; t < taps; ++t) {
    const double d = t - half;
    kernel[t] = static_cast<float>(std::exp(-d * d / (2 * sigma * sigma)));
    sum += kernel[t];
  }
  for (int32_t t = 0; t < taps; ++t) kernel[t] /= sum;
  const size_t row = static_cast<size_t>(width) * 3;
  if (tmp.size() < row * static_cast<size_t>(height)) tmp.resize(row * static_cast<size_t>(height));
  for (int32_t y = 0; y < height; ++y) {
    blur_line(f + static_cast<size_t>(y) * row, tmp.data() + static_cast<size_t>(y) * row, width, 3,
              kernel, taps);
  }
  for (int32_t x = 0; x < width; ++x) {
    blur_line(tmp.data() + static_cast<size_t>(x) * 3, f + static_cast<size_t>(x) * 3, height, row,
              kernel, taps);
  }
}

void add_noise(float* f, size_t values, double sigma, uint64_t seed) {
  // Irwin-Hall: four 16-bit uniforms of one 64-bit draw, centred and scaled to unit variance
  // (a sum of four uniforms has variance 4/12). One draw per value keeps a 230k-value frame
  // cheap; a camera's noise is not exactly normal either.
  constexpr float kScale = 1.7320508f / 65536.0f;  // sqrt(3) / 2^16
  uint64_t state = seed;
  const auto s = static_cast<float>(sigma);
  for (size_t i = 0; i < values; ++i) {
    const uint64_t z = rng::splitmix(state);
    const auto sum =
        static_cast<float>((z & 0xffff) + ((z >> 16) & 0xffff) + ((z >> 32) & 0xffff) + (z >> 48));
    f[i] += s * (sum - 2.0f * 65535.0f) * kScale;
  }
}

void to_uint8(const float* f, uint8_t* out, size_t values) {
  // Clamped to [0, 255] first, so + 0.5 and truncation round half away from zero.
  for (size_t i = 0; i < values; ++i) {
    out[i] = static_cast<uint8_t>(std::clamp(f[i], 0.0f, 255.0f) + 0.5f);
  }
}

}  // namespace tlvlink::trainer::view
