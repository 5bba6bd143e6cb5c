#include "render/texture.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "render/model_constants.h"
#include "render/rng.h"

namespace tlvlink::sim::internal {
namespace {

inline float smooth(float f) { return f * f * (3.0f - 2.0f * f); }

}  // namespace

FractalTexture::FractalTexture(const FrameGrid& grid)
    : grid_(grid),
      tex_(grid.pixels()),
      cell_x_(static_cast<size_t>(grid.width)),
      weight_x_(static_cast<size_t>(grid.width)),
      lattice_a_(static_cast<size_t>(grid.width) + 4),
      lattice_b_(static_cast<size_t>(grid.width) + 4),
      row_(static_cast<size_t>(grid.width) + 4) {}

void FractalTexture::add(const SurfaceTexture& t, double origin_x_mm, double origin_y_mm, Roi roi,
                         float* h, Roi stats) {
  if (!(t.sq_um > 0) || roi.empty()) return;
  const int32_t w = roi.width(), hh = roi.height();
  const size_t n = static_cast<size_t>(w) * static_cast<size_t>(hh);
  std::fill(tex_.begin(), tex_.begin() + static_cast<ptrdiff_t>(n), 0.0f);
  const double min_lambda = kMinWavelengthPx * grid_.mm_per_px;
  double lambda = std::max(t.correlation_length_mm, min_lambda);
  for (int k = 0; k < kMaxOctaves && lambda >= min_lambda; ++k, lambda *= 0.5) {
    const float amp = static_cast<float>(std::exp2(-k * t.hurst));
    const uint64_t octave_seed = mix64(t.seed ^ (0xC0FFEEull + static_cast<uint64_t>(k)));
    // Columns: lattice cell (monotone in x) and weight.
    const double ix0 = std::floor((grid_.x_mm(roi.x0) - origin_x_mm) / lambda);
    for (int32_t x = 0; x < w; ++x) {
      const double u = (grid_.x_mm(roi.x0 + x) - origin_x_mm) / lambda;
      const double iu = std::floor(u);
      cell_x_[static_cast<size_t>(x)] = static_cast<int32_t>(iu - ix0);
      weight_x_[static_cast<size_t>(x)] = smooth(static_cast<float>(u - iu));
    }
    const int32_t cols = cell_x_[static_cast<size_t>(w - 1)] + 2;
    const auto base_x = static_cast<int64_t>(ix0);
    auto fill = [&](std::vector<float>& lat, int64_t iy) {
      for (int32_t i = 0; i < cols; ++i) {
        lat[static_cast<size_t>(i)] = hash_to_signed_unit(hash3(octave_seed, base_x + i, iy));
      }
    };
    int64_t have = INT64_MIN;  // lattice row held in lattice_a_
    for (int32_t y = 0; y < hh; ++y) {
      const double v = (grid_.y_mm(roi.y0 + y) - origin_y_mm) / lambda;
      const double iv = std::floor(v);
      const auto iy = static_cast<int64_t>(iv);
      if (iy != have) {
        if (have != INT64_MIN && iy == have + 1) {
          std::swap(lattice_a_, lattice_b_);
        } else {
          fill(lattice_a_, iy);
        }
        fill(lattice_b_, iy + 1);
        have = iy;
      }
      const float wy = smooth(static_cast<float>(v - iv));
      for (int32_t i = 0; i < cols; ++i) {
        const float a = lattice_a_[static_cast<size_t>(i)];
        row_[static_cast<size_t>(i)] = a + (lattice_b_[static_cast<size_t>(i)] - a) * wy;
      }
      float* out = tex_.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
      for (int32_t x = 0; x < w; ++x) {
        const auto c = static_cast<size_t>(cell_x_[static_cast<size_t>(x)]);
        const float r0 = row_[c], r1 = row_[c + 1];
        out[x] += amp * (r0 + (r1 - r0) * weight_x_[static_cast<size_t>(x)]);
      }
    }
  }
  // Statistics over roi ∩ stats, in roi-relative coordinates (row-major, as tex_ is laid out).
  Roi s{std::max(roi.x0, stats.x0) - roi.x0, std::max(roi.y0, stats.y0) - roi.y0,
        std::min(roi.x1, stats.x1) - roi.x0, std::min(roi.y1, stats.y1) - roi.y0};
  if (stats.empty() || s.empty()) s = {0, 0, w, hh};
  double sum = 0, sum_sq = 0;
  for (int32_t y = s.y0; y < s.y1; ++y) {
    const float* tr = tex_.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
    for (int32_t x = s.x0; x < s.x1; ++x) {
      const auto v = static_cast<double>(tr[x]);
      sum += v;
      sum_sq += v * v;
    }
  }
  const auto count = static_cast<double>(s.width()) * static_cast<double>(s.height());
  const double mean = sum / count;
  const double var = std::max(0.0, sum_sq / count - mean * mean);
  if (!(var > 0)) return;
  const auto scale = static_cast<float>(t.sq_um * 1e-3 / std::sqrt(var));
  const auto m = static_cast<float>(mean);
  for (int32_t y = 0; y < hh; ++y) {
    float* tr = tex_.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
    float* hr = h + static_cast<size_t>(roi.y0 + y) * static_cast<size_t>(grid_.width) +
                static_cast<size_t>(roi.x0);
    for (int32_t x = 0; x < w; ++x) {
      tr[x] = (tr[x] - m) * scale;
      hr[x] += tr[x];
    }
  }
}

}  // namespace tlvlink::sim::internal
