#include "render/spreading.h"

#include <algorithm>
#include <cmath>

#include "render/model_constants.h"

namespace tlvlink::sim::internal {
namespace {

constexpr double kRoiSigmas = 3.5;  // exp(-3.5^2 / 2) = 0.2 %: the tail left outside the ROI

}  // namespace

std::vector<double> spreading_sigmas_px(double gel_thickness_mm, double mm_per_px) {
  std::vector<double> s;
  for (double mm : kSpreadSigmasMm) {
    s.push_back(mm * gel_thickness_mm / kSpreadReferenceThicknessMm / mm_per_px);
  }
  return s;
}

MembraneSpreading::MembraneSpreading(const FrameGrid& grid, double gel_thickness_mm)
    : grid_(grid), z_(grid.pixels()), u_(grid.pixels()) {
  const auto s = spreading_sigmas_px(gel_thickness_mm, grid.mm_per_px);
  double var = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    sigmas_px_[i] = s[i];
    var += s[i] * s[i];
  }
  // Gaussians compose by variance; +2 for the final 5x5 blur, +1 for the slope stencil.
  margin_px_ = static_cast<int32_t>(std::ceil(kRoiSigmas * std::sqrt(var))) + 3;
}

Roi MembraneSpreading::roi(const ContactSolution& c) const {
  if (!c.in_contact) return {};
  return {std::max(0, c.x0 - margin_px_), std::max(0, c.y0 - margin_px_),
          std::min(grid_.width, c.x1 + margin_px_), std::min(grid_.height, c.y1 + margin_px_)};
}

PlaneView MembraneSpreading::spread(const float* u_gel, double max_gel, Roi roi,
                                    GaussianBlur& blur) {
  const int32_t w = roi.width(), h = roi.height();
  PlaneView z{z_.data(), w, h, w};
  if (roi.empty()) return z;
  // Frame borders continue the gel (replicate); ROI sides inside the frame border zeros.
  EdgeModes edges;
  edges.left = roi.x0 == 0 ? EdgeMode::kReplicate : EdgeMode::kZero;
  edges.top = roi.y0 == 0 ? EdgeMode::kReplicate : EdgeMode::kZero;
  edges.right = roi.x1 == grid_.width ? EdgeMode::kReplicate : EdgeMode::kZero;
  edges.bottom = roi.y1 == grid_.height ? EdgeMode::kReplicate : EdgeMode::kZero;
  const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
  for (int32_t y = 0; y < h; ++y) {
    const float* src = u_gel + static_cast<size_t>(roi.y0 + y) * static_cast<size_t>(grid_.width) +
                       static_cast<size_t>(roi.x0);
    float* zu = u_.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
    float* zr = z.row(y);
    for (int32_t x = 0; x < w; ++x) {
      zu[x] = -src[x];
      zr[x] = -src[x];
    }
  }
  // Core: u > 0.4 max u, i.e. -u < -0.4 max u.
  const auto core = static_cast<float>(-kCoreFraction * max_gel);
  for (double sigma : sigmas_px_) {
    blur.blur(z, sigma, edges);
    const float* cu = u_.data();
    float* zz = z.data;
    for (size_t i = 0; i < n; ++i) zz[i] = cu[i] < core ? cu[i] : zz[i];
  }
  blur.blur_direct(z, kCameraBlurSigmaPx, kCameraBlurRadiusPx, edges);
  return z;
}

}  // namespace tlvlink::sim::internal
