#include "render/blur.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace tlvlink::sim::internal {
namespace {

// Normalised Gaussian taps k[0..radius] (k[0] the centre).
void gaussian_taps(double sigma, int32_t radius, float* k) {
  double sum = 0;
  double w[kMaxDirectRadius + 1];
  for (int32_t i = 0; i <= radius; ++i) {
    w[i] = std::exp(-0.5 * i * i / (sigma * sigma));
    sum += i == 0 ? w[i] : 2 * w[i];
  }
  for (int32_t i = 0; i <= radius; ++i) k[i] = static_cast<float>(w[i] / sum);
}

// Deriche (1993) fourth-order recursive Gaussian: y = (y+ + y-) / S with
// y+[n] = sum_k n_k x[n-k] - sum_k d_k y+[n-k], y-[n] = sum_k m_k x[n+k] - sum_k d_k y-[n+k].
// Within ~0.05 % of the peak of a true Gaussian for sigma >= 1 (tests/sim/render).
struct DericheCoefficients {
  float n[4];                          // causal input taps x[n], x[n-1], x[n-2], x[n-3]
  float m[4];                          // anti-causal input taps x[n+1] .. x[n+4]
  float d[4];                          // feedback y[n -+ 1] .. y[n -+ 4]
  float causal_gain, anticausal_gain;  // steady state of y+ and y- for a unit constant input
  float inv_sum;                       // 1 / (causal_gain + anticausal_gain)
};

DericheCoefficients deriche_coefficients(double s) {
  constexpr double a0 = 1.680, a1 = 3.735, b0 = 1.783, b1 = 1.723, c0 = -0.6803, c1 = -0.2598;
  constexpr double w0 = 0.6318, w1 = 1.997;
  const double e0 = std::exp(-b0 / s), e1 = std::exp(-b1 / s);
  const double cw0 = std::cos(w0 / s), sw0 = std::sin(w0 / s);
  const double cw1 = std::cos(w1 / s), sw1 = std::sin(w1 / s);
  const double n0 = a0 + c0;
  const double n1 = e1 * (c1 * sw1 - (c0 + 2 * a0) * cw1) + e0 * (a1 * sw0 - (2 * c0 + a0) * cw0);
  const double n2 = 2 * e0 * e1 * ((a0 + c0) * cw1 * cw0 - a1 * cw1 * sw0 - c1 * cw0 * sw1) +
                    c0 * e0 * e0 + a0 * e1 * e1;
  const double n3 = e1 * e0 * e0 * (c1 * sw1 - c0 * cw1) + e0 * e1 * e1 * (a1 * sw0 - a0 * cw0);
  const double d4 = e0 * e0 * e1 * e1;
  const double d3 = -2 * cw0 * e0 * e1 * e1 - 2 * cw1 * e1 * e0 * e0;
  const double d2 = 4 * cw1 * cw0 * e0 * e1 + e1 * e1 + e0 * e0;
  const double d1 = -2 * e1 * cw1 - 2 * e0 * cw0;
  const double m1 = n1 - d1 * n0, m2 = n2 - d2 * n0, m3 = n3 - d3 * n0, m4 = -d4 * n0;
  DericheCoefficients k;
  const double nn[4] = {n0, n1, n2, n3}, mm[4] = {m1, m2, m3, m4}, dd[4] = {d1, d2, d3, d4};
  for (int i = 0; i < 4; ++i) {
    k.n[i] = static_cast<float>(nn[i]);
    k.m[i] = static_cast<float>(mm[i]);
    k.d[i] = static_cast<float>(dd[i]);
  }
  // Gains from the float taps, so a constant field stays constant to float rounding.
  float fd = 1, fn = 0, fm = 0;
  for (int i = 0; i < 4; ++i) {
    fd += k.d[i];
    fn += k.n[i];
    fm += k.m[i];
  }
  k.causal_gain = fn / fd;
  k.anticausal_gain = fm / fd;
  k.inv_sum = 1.0f / (k.causal_gain + k.anticausal_gain);
  return k;
}

// out += k * (a + b); out never aliases a or b (restrict lets the loop vectorise).
[[gnu::noinline]] void add_pair(float* __restrict out, const float* a, const float* b, float k,
                                int32_t w) {
  for (int32_t x = 0; x < w; ++x) out[x] += k * (a[x] + b[x]);
}

[[gnu::noinline]] void scale_row(float* __restrict out, const float* __restrict in, float k,
                                 int32_t w) {
  for (int32_t x = 0; x < w; ++x) out[x] = k * in[x];
}

// out = t0 x0 + t1 x1 + t2 x2 + t3 x3 - d0 y0 - d1 y1 - d2 y2 - d3 y3 over a row.
[[gnu::noinline]] void recursive_step(float* __restrict out, const float* const x[4],
                                      const float t[4], const float* const y[4], const float d[4],
                                      int32_t w) {
  const float* x0 = x[0];
  const float* x1 = x[1];
  const float* x2 = x[2];
  const float* x3 = x[3];
  const float* y0 = y[0];
  const float* y1 = y[1];
  const float* y2 = y[2];
  const float* y3 = y[3];
  for (int32_t i = 0; i < w; ++i) {
    out[i] = t[0] * x0[i] + t[1] * x1[i] + t[2] * x2[i] + t[3] * x3[i] -
             (d[0] * y0[i] + d[1] * y1[i] + d[2] * y2[i] + d[3] * y3[i]);
  }
}

}  // namespace

GaussianBlur::GaussianBlur(int32_t max_width, int32_t max_height)
    : temp_(static_cast<size_t>(max_width) * static_cast<size_t>(max_height)),
      transposed_(temp_.size()),
      line_(static_cast<size_t>(std::max(max_width, max_height) + 2 * kMaxDirectRadius)),
      rows_(kScratchRows * static_cast<size_t>(std::max(max_width, max_height))),
      zero_row_(static_cast<size_t>(std::max(max_width, max_height)), 0.0f) {}

void transpose(PlaneView src, PlaneView dst) {
  constexpr int32_t kTile = 16;  // keeps both sides of the copy in cache
  for (int32_t y0 = 0; y0 < src.height; y0 += kTile) {
    const int32_t y1 = std::min(y0 + kTile, src.height);
    for (int32_t x0 = 0; x0 < src.width; x0 += kTile) {
      const int32_t x1 = std::min(x0 + kTile, src.width);
      for (int32_t y = y0; y < y1; ++y) {
        const float* s = src.row(y);
        for (int32_t x = x0; x < x1; ++x) dst.data[x * dst.stride + y] = s[x];
      }
    }
  }
}

void GaussianBlur::blur(PlaneView plane, double sigma_px, EdgeModes edges) {
  if (plane.width <= 0 || plane.height <= 0 || !(sigma_px > 0)) return;
  if (sigma_px < kRecursiveMinSigma) {
    const int32_t radius =
        std::min<int32_t>(kMaxDirectRadius, static_cast<int32_t>(std::ceil(3 * sigma_px)));
    blur_direct(plane, sigma_px, radius, edges);
    return;
  }
  recursive_columns(plane, sigma_px, edges.top, edges.bottom);
  PlaneView t{transposed_.data(), plane.height, plane.width, plane.height};
  transpose(plane, t);
  recursive_columns(t, sigma_px, edges.left, edges.right);
  transpose(t, plane);
}

void GaussianBlur::recursive_columns(PlaneView p, double sigma_px, EdgeMode top, EdgeMode bottom) {
  const DericheCoefficients k = deriche_coefficients(sigma_px);
  const int32_t w = p.width, h = p.height;
  const size_t row_bytes = sizeof(float) * static_cast<size_t>(w);
  const size_t stride = rows_.size() / kScratchRows;
  auto scratch = [&](int i) { return rows_.data() + static_cast<size_t>(i) * stride; };
  // Beyond each end: zeros, or the edge row with the filters in their steady state.
  float* x_top = scratch(0);
  float* y_top = scratch(1);
  float* x_bottom = scratch(2);
  float* y_bottom = scratch(3);
  for (int32_t i = 0; i < w; ++i) {
    const float a = top == EdgeMode::kReplicate ? p.row(0)[i] : 0.0f;
    const float b = bottom == EdgeMode::kReplicate ? p.row(h - 1)[i] : 0.0f;
    x_top[i] = a;
    y_top[i] = a * k.causal_gain;
    x_bottom[i] = b;
    y_bottom[i] = b * k.anticausal_gain;
  }
  // Causal pass into temp_ (the input rows stay intact for the anti-causal pass).
  float* yp = temp_.data();
  auto yp_row = [&](int32_t y) {
    return y >= 0 ? yp + static_cast<size_t>(y) * static_cast<size_t>(w) : y_top;
  };
  for (int32_t y = 0; y < h; ++y) {
    const float* x[4];
    const float* yy[4];
    for (int j = 0; j < 4; ++j) {
      x[j] = y - j >= 0 ? p.row(y - j) : x_top;
      yy[j] = yp_row(y - 1 - j);
    }
    recursive_step(yp + static_cast<size_t>(y) * static_cast<size_t>(w), x, k.n, yy, k.d, w);
  }
  // Anti-causal pass from the bottom; rings of five rows keep the original inputs and y- of the
  // four rows below, since the output overwrites the plane row by row.
  float* x_ring[5];
  float* y_ring[5];
  for (int j = 0; j < 5; ++j) {
    x_ring[j] = scratch(4 + j);
    y_ring[j] = scratch(9 + j);
  }
  for (int32_t y = h - 1; y >= 0; --y) {
    std::memcpy(x_ring[y % 5], p.row(y), row_bytes);
    const float* x[4];
    const float* yy[4];
    for (int j = 0; j < 4; ++j) {
      const int32_t below = y + 1 + j;
      x[j] = below < h ? x_ring[below % 5] : x_bottom;
      yy[j] = below < h ? y_ring[below % 5] : y_bottom;
    }
    float* ym = y_ring[y % 5];
    recursive_step(ym, x, k.m, yy, k.d, w);
    float* out = p.row(y);
    const float* causal = yp_row(y);
    for (int32_t i = 0; i < w; ++i) out[i] = (causal[i] + ym[i]) * k.inv_sum;
  }
}

void GaussianBlur::blur_direct(PlaneView plane, double sigma_px, int32_t radius, EdgeModes edges) {
  if (plane.width <= 0 || plane.height <= 0 || !(sigma_px > 0)) return;
  radius = std::clamp<int32_t>(radius, 1, kMaxDirectRadius);
  float kernel[kMaxDirectRadius + 1];
  gaussian_taps(sigma_px, radius, kernel);
  PlaneView tmp{temp_.data(), plane.width, plane.height, plane.width};
  direct_columns(plane, tmp, kernel, radius, edges.top, edges.bottom);
  direct_rows(tmp, plane, kernel, radius, edges.left, edges.right);
}

void GaussianBlur::direct_columns(PlaneView src, PlaneView dst, const float* kernel, int32_t radius,
                                  EdgeMode top, EdgeMode bottom) {
  const int32_t w = src.width, h = src.height;
  const float* zero = zero_row_.data();
  for (int32_t y = 0; y < h; ++y) {
    float* out = dst.row(y);
    scale_row(out, src.row(y), kernel[0], w);
    for (int32_t i = 1; i <= radius; ++i) {
      const float* up = y - i >= 0 ? src.row(y - i) : (top == EdgeMode::kZero ? zero : src.row(0));
      const float* down =
          y + i < h ? src.row(y + i) : (bottom == EdgeMode::kZero ? zero : src.row(h - 1));
      add_pair(out, up, down, kernel[i], w);
    }
  }
}

void GaussianBlur::direct_rows(PlaneView src, PlaneView dst, const float* kernel, int32_t radius,
                               EdgeMode left, EdgeMode right) {
  const int32_t w = src.width;
  float* line = line_.data();
  for (int32_t y = 0; y < src.height; ++y) {
    const float* in = src.row(y);
    std::memcpy(line + radius, in, sizeof(float) * static_cast<size_t>(w));
    const float lv = left == EdgeMode::kZero ? 0.0f : in[0];
    const float rv = right == EdgeMode::kZero ? 0.0f : in[w - 1];
    for (int32_t i = 0; i < radius; ++i) {
      line[i] = lv;
      line[radius + w + i] = rv;
    }
    float* out = dst.row(y);
    const float* mid = line + radius;
    scale_row(out, mid, kernel[0], w);
    for (int32_t i = 1; i <= radius; ++i) add_pair(out, mid - i, mid + i, kernel[i], w);
  }
}

}  // namespace tlvlink::sim::internal
