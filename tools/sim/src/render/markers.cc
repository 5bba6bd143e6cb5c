#include "render/markers.h"

#include <algorithm>
#include <cmath>

#include "render/model_constants.h"

namespace tlvlink::sim::internal {
namespace {

// Blocks farther than this from a marker contribute < exp(-3.5^2 / 2) of the peak.
constexpr double kDilationWindowSigmas = 3.5;

}  // namespace

MarkerPainter::MarkerPainter(const FrameGrid& grid, const SensorProfile& profile)
    : grid_(grid),
      blocks_x_((grid.width + kBlock - 1) / kBlock),
      blocks_y_((grid.height + kBlock - 1) / kBlock),
      block_u_(static_cast<size_t>(blocks_x_) * static_cast<size_t>(blocks_y_)),
      ex_(static_cast<size_t>(blocks_x_)),
      ey_(static_cast<size_t>(blocks_y_)) {
  sigma_px_ = std::max(0.5, kMarkerSigmaPerRadius * profile.marker_radius_mm / grid.mm_per_px);
  radius_px_ = static_cast<int32_t>(std::ceil(3 * sigma_px_));
  dot_x_.resize(static_cast<size_t>(2 * radius_px_ + 1));
  dot_y_.resize(static_cast<size_t>(2 * radius_px_ + 1));
}

void MarkerPainter::prepare_dilation(const float* u, const ContactSolution& c) {
  bx0_ = by0_ = bx1_ = by1_ = 0;
  if (!c.in_contact) return;
  bx0_ = c.x0 / kBlock;
  by0_ = c.y0 / kBlock;
  bx1_ = (c.x1 + kBlock - 1) / kBlock;
  by1_ = (c.y1 + kBlock - 1) / kBlock;
  const auto area = static_cast<float>(grid_.mm_per_px * grid_.mm_per_px);
  for (int32_t by = by0_; by < by1_; ++by) {
    for (int32_t bx = bx0_; bx < bx1_; ++bx) {
      float sum = 0;
      const int32_t ye = std::min(grid_.height, (by + 1) * kBlock);
      const int32_t xe = std::min(grid_.width, (bx + 1) * kBlock);
      for (int32_t y = by * kBlock; y < ye; ++y) {
        const float* row = u + static_cast<size_t>(y) * static_cast<size_t>(grid_.width);
        for (int32_t x = bx * kBlock; x < xe; ++x) sum += row[x];
      }
      block_u_[static_cast<size_t>(by * blocks_x_ + bx)] = sum * area;
    }
  }
}

std::array<double, 2> MarkerPainter::dilation(double x_mm, double y_mm) {
  if (bx1_ <= bx0_) return {0, 0};
  const double lambda = kDilationLambdaPerMm2;
  const double window = kDilationWindowSigmas / std::sqrt(2 * lambda);
  const double block_mm = kBlock * grid_.mm_per_px;
  // Block centre (mm) of block index b along an axis with `pixels` pixels, and the block range
  // [lo, hi) within `window` of position `mm` (clamped to the contact's blocks [b0, b1)).
  auto centre = [&](int32_t b, int32_t pixels) {
    return ((b + 0.5) * kBlock - 0.5 * pixels) * grid_.mm_per_px;
  };
  auto range = [&](double mm, int32_t pixels, int32_t b0, int32_t b1, int32_t& lo, int32_t& hi) {
    const double first = (mm - window) / block_mm + 0.5 * pixels / kBlock;
    const double last = (mm + window) / block_mm + 0.5 * pixels / kBlock;
    lo = std::max(b0, static_cast<int32_t>(std::max(std::floor(first), -1.0)));
    hi = std::min(b1, static_cast<int32_t>(std::min(std::ceil(last), 1e6)) + 1);
  };
  int32_t bx_lo, bx_hi, by_lo, by_hi;
  range(x_mm, grid_.width, bx0_, bx1_, bx_lo, bx_hi);
  range(y_mm, grid_.height, by0_, by1_, by_lo, by_hi);
  if (bx_lo >= bx_hi || by_lo >= by_hi) return {0, 0};
  for (int32_t bx = bx_lo; bx < bx_hi; ++bx) {
    const double d = x_mm - centre(bx, grid_.width);
    ex_[static_cast<size_t>(bx)] = std::exp(-lambda * d * d);
  }
  for (int32_t by = by_lo; by < by_hi; ++by) {
    const double d = y_mm - centre(by, grid_.height);
    ey_[static_cast<size_t>(by)] = std::exp(-lambda * d * d);
  }
  double dx = 0, dy = 0;
  for (int32_t by = by_lo; by < by_hi; ++by) {
    const double ry = y_mm - centre(by, grid_.height), wy = ey_[static_cast<size_t>(by)];
    for (int32_t bx = bx_lo; bx < bx_hi; ++bx) {
      const auto v = static_cast<double>(block_u_[static_cast<size_t>(by * blocks_x_ + bx)]);
      if (v == 0) continue;
      const double wgt = v * wy * ex_[static_cast<size_t>(bx)];
      dx += wgt * (x_mm - centre(bx, grid_.width));
      dy += wgt * ry;
    }
  }
  dx *= kDilationCoefficient;
  dy *= kDilationCoefficient;
  const double mag = std::hypot(dx, dy);
  if (mag > kMaxDilationMm) {
    dx *= kMaxDilationMm / mag;
    dy *= kMaxDilationMm / mag;
  }
  return {dx, dy};
}

void MarkerPainter::draw(double x_px, double y_px, const std::array<const float*, 3>& background,
                         const std::array<float*, 3>& delta, Roi& dirty) {
  // Pixel centres sit at integer + 0.5 in this continuous coordinate.
  const auto cx = static_cast<int32_t>(std::floor(x_px)),
             cy = static_cast<int32_t>(std::floor(y_px));
  const int32_t x0 = std::max(0, cx - radius_px_), x1 = std::min(grid_.width, cx + radius_px_ + 1);
  const int32_t y0 = std::max(0, cy - radius_px_), y1 = std::min(grid_.height, cy + radius_px_ + 1);
  if (x0 >= x1 || y0 >= y1) return;
  const double k = 0.5 / (sigma_px_ * sigma_px_);
  for (int32_t x = x0; x < x1; ++x) {
    const double d = x + 0.5 - x_px;
    dot_x_[static_cast<size_t>(x - x0)] = static_cast<float>(kMarkerDepth * std::exp(-k * d * d));
  }
  for (int32_t y = y0; y < y1; ++y) {
    const double d = y + 0.5 - y_px;
    dot_y_[static_cast<size_t>(y - y0)] = static_cast<float>(std::exp(-k * d * d));
  }
  for (int c = 0; c < 3; ++c) {
    const float* b = background[static_cast<size_t>(c)];
    float* dd = delta[static_cast<size_t>(c)];
    for (int32_t y = y0; y < y1; ++y) {
      const size_t row = static_cast<size_t>(y) * static_cast<size_t>(grid_.width);
      const float wy = dot_y_[static_cast<size_t>(y - y0)];
      for (int32_t x = x0; x < x1; ++x) {
        const float m = wy * dot_x_[static_cast<size_t>(x - x0)];
        dd[row + static_cast<size_t>(x)] -=
            (b[row + static_cast<size_t>(x)] + dd[row + static_cast<size_t>(x)]) * m;
      }
    }
  }
  if (dirty.empty()) {
    dirty = {x0, y0, x1, y1};
  } else {
    dirty = {std::min(dirty.x0, x0), std::min(dirty.y0, y0), std::max(dirty.x1, x1),
             std::max(dirty.y1, y1)};
  }
}

}  // namespace tlvlink::sim::internal
