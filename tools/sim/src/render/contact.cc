#include "render/contact.h"

#include <algorithm>
#include <cmath>

#include "render/model_constants.h"

namespace tlvlink::sim::internal {
namespace {

inline double dbl(float v) { return static_cast<double>(v); }

}  // namespace

Compliance compliance(const SensorProfile& s, const ObjectMechanics& o) {
  Compliance c;
  const double cg =
      std::max((1 - s.gel_poisson * s.gel_poisson) / s.gel_modulus_pa, kMinCompliancePerPa);
  const double co = std::max((1 - o.poisson * o.poisson) / o.modulus_pa, kMinCompliancePerPa);
  const double gel = cg * s.gel_thickness_mm, obj = co * o.local_radius_mm;
  c.kappa = std::clamp(gel / (gel + obj), 1e-12, 1.0);
  const double e_gel = s.gel_modulus_pa * 1e-6;  // N/mm^2
  c.winkler = kChi * e_gel / (1 - s.gel_poisson * s.gel_poisson) / s.gel_thickness_mm;
  c.tension = kPsi * e_gel * s.gel_thickness_mm / (6 * (1 + s.gel_poisson));
  c.max_gel_mm = kMaxGelStrain * s.gel_thickness_mm;
  c.max_press_mm = c.max_gel_mm / c.kappa;
  if (o.layer_mm > 0) {
    c.layer_cap_mm = kMaxLayerStrain * o.layer_mm;
    // The object's share (1 - kappa) a reaches the cap at a = cap / (1 - kappa).
    const double reach = c.layer_cap_mm / std::max(1 - c.kappa, 1e-300);
    if (reach < c.max_press_mm) {
      c.capped = true;
      c.capped_max_press_mm = std::min(c.max_press_mm, c.max_gel_mm + c.layer_cap_mm);
    }
  }
  return c;
}

double texture_split(const SensorProfile& s, const ObjectMechanics& o, const SurfaceTexture& t) {
  const double cg =
      std::max((1 - s.gel_poisson * s.gel_poisson) / s.gel_modulus_pa, kMinCompliancePerPa);
  const double co = std::max((1 - o.poisson * o.poisson) / o.modulus_pa, kMinCompliancePerPa);
  const double l = t.correlation_length_mm;
  const double gel = cg * std::min(l, s.gel_thickness_mm);
  const double obj = co * (o.layer_mm > 0 ? std::min(l, o.layer_mm) : l);
  return std::clamp(gel / (gel + obj), 1e-12, 1.0);
}

ContactSolver::ContactSolver(const FrameGrid& grid)
    : grid_(grid),
      area_px_(grid.mm_per_px * grid.mm_per_px),
      gap_(grid.pixels()),
      bin_count_(kGapBins),
      bin_gap_(kGapBins),
      bin_curv_(kGapBins),
      in_bin_gap_(grid.pixels()),
      in_bin_curv_(grid.pixels()) {}

void ContactSolver::prepare(const float* h, const float* curvature, const Compliance& c,
                            Roi surface) {
  c_ = c;
  curvature_ = curvature;
  surface_ = surface;
  gap_max_ = 0;
  if (surface.empty()) return;
  const size_t w = static_cast<size_t>(grid_.width);
  float top = h[static_cast<size_t>(surface.y0) * w + static_cast<size_t>(surface.x0)];
  for (int32_t y = surface.y0; y < surface.y1; ++y) {
    const float* r = h + static_cast<size_t>(y) * w;
    for (int32_t x = surface.x0; x < surface.x1; ++x) top = std::max(top, r[x]);
  }
  float gmax = 0;
  const auto limit = static_cast<float>(kSurfaceGapLimitMm);
  for (int32_t y = surface.y0; y < surface.y1; ++y) {
    const float* r = h + static_cast<size_t>(y) * w;
    float* g = gap_.data() + static_cast<size_t>(y) * w;
    for (int32_t x = surface.x0; x < surface.x1; ++x) {
      g[x] = top - r[x];
      gmax = std::max(gmax, g[x] < limit ? g[x] : 0.0f);
    }
  }
  gap_max_ = dbl(gmax);
}

double ContactSolver::capped_force_at(double press) const {
  double winkler = 0, tension = 0;
  const auto d = static_cast<float>(press);
  const auto kappa = static_cast<float>(c_.kappa), cap = static_cast<float>(c_.layer_cap_mm);
  const auto gel_cap = static_cast<float>(c_.max_gel_mm);
  const size_t w = static_cast<size_t>(grid_.width);
  for (int32_t y = surface_.y0; y < surface_.y1; ++y) {
    for (int32_t x = surface_.x0; x < surface_.x1; ++x) {
      const size_t i = static_cast<size_t>(y) * w + static_cast<size_t>(x);
      if (gap_[i] < d) {
        const float a = d - gap_[i];
        const float ug = std::min(std::max(kappa * a, a - cap), gel_cap);
        winkler += dbl(ug);
        tension += dbl(curvature_[i]) * dbl(ug) / dbl(a);
      }
    }
  }
  return c_.winkler * area_px_ * winkler + c_.tension * tension;
}

double ContactSolver::force_at(double press) const {
  if (cap_reached(press)) return capped_force_at(press);
  double winkler = 0, tension = 0;
  const auto d = static_cast<float>(press);
  const size_t w = static_cast<size_t>(grid_.width);
  for (int32_t y = surface_.y0; y < surface_.y1; ++y) {
    for (int32_t x = surface_.x0; x < surface_.x1; ++x) {
      const size_t i = static_cast<size_t>(y) * w + static_cast<size_t>(x);
      if (gap_[i] < d) {
        winkler += dbl(d - gap_[i]);
        tension += dbl(curvature_[i]);
      }
    }
  }
  return c_.kappa * (c_.winkler * area_px_ * winkler + c_.tension * tension);
}

double ContactSolver::press_for_force(double target) {
  if (!(target > 0) || surface_.empty()) return 0;
  const double d = uncapped_press_for_force(target);
  if (!cap_reached(d)) return d;  // the capped F equals the uncapped one up to this depth
  // Plain bisection: the cap makes F piecewise in each pixel, so the histogram sums no longer
  // give F at the bin edges. The capped F is above the uncapped one, so the press is below d.
  double lo = 0, hi = std::min(d, c_.capped_max_press_mm);
  if (capped_force_at(hi) <= target) return hi;
  double p = hi;
  for (int it = 0; it < kMaxBisection; ++it) {
    p = 0.5 * (lo + hi);
    const double f = capped_force_at(p);
    if (std::fabs(f - target) < kForceRelTolerance * target) break;
    (f < target ? lo : hi) = p;
  }
  return p;
}

double ContactSolver::uncapped_press_for_force(double target) {
  const double kk = c_.kappa * c_.winkler * area_px_, kt = c_.kappa * c_.tension;
  const double hi = std::min(c_.max_press_mm, gap_max_);
  const size_t w = static_cast<size_t>(grid_.width);
  std::fill(bin_count_.begin(), bin_count_.end(), 0.0);
  std::fill(bin_gap_.begin(), bin_gap_.end(), 0.0);
  std::fill(bin_curv_.begin(), bin_curv_.end(), 0.0);
  // Totals over the object's surface (pixels without surface never touch, see kNoSurfaceMm).
  double all_count = 0, all_gap = 0, all_curv = 0;
  const double per_bin = hi > 0 ? kGapBins / hi : 0;
  auto bin_of = [per_bin](double g) {
    return std::min<size_t>(kGapBins - 1, static_cast<size_t>(g * per_bin));
  };
  for (int32_t y = surface_.y0; y < surface_.y1; ++y) {
    for (int32_t x = surface_.x0; x < surface_.x1; ++x) {
      const size_t i = static_cast<size_t>(y) * w + static_cast<size_t>(x);
      const double g = dbl(gap_[i]);
      if (!(g < kSurfaceGapLimitMm)) continue;
      all_count += 1;
      all_gap += g;
      all_curv += dbl(curvature_[i]);
      if (g < hi) {
        const size_t b = bin_of(g);
        bin_count_[b] += 1;
        bin_gap_[b] += g;
        bin_curv_[b] += dbl(curvature_[i]);
      }
    }
  }
  // F at bin edge j uses the bins below j; find the bin where F crosses the target.
  auto edge = [hi](int j) { return hi * j / kGapBins; };
  double cnt = 0, sg = 0, sc = 0;
  int j = 0;
  for (; j < kGapBins; ++j) {
    const double next_cnt = cnt + bin_count_[static_cast<size_t>(j)];
    const double next_sg = sg + bin_gap_[static_cast<size_t>(j)];
    const double next_sc = sc + bin_curv_[static_cast<size_t>(j)];
    const double f_next = kk * (edge(j + 1) * next_cnt - next_sg) + kt * next_sc;
    if (f_next > target) break;
    cnt = next_cnt;
    sg = next_sg;
    sc = next_sc;
  }
  if (j == kGapBins) {  // beyond the histogram: all surface in contact (F linear) or the limit
    const double deepest = std::min(c_.max_press_mm, kSurfaceGapLimitMm);
    if (hi >= deepest) return deepest;
    const double d = ((target - kt * all_curv) / kk + all_gap) / all_count;
    return std::clamp(d, hi, deepest);
  }
  // Exact bisection inside bin j with only that bin's pixels.
  size_t m = 0;
  for (int32_t y = surface_.y0; y < surface_.y1; ++y) {
    for (int32_t x = surface_.x0; x < surface_.x1; ++x) {
      const size_t i = static_cast<size_t>(y) * w + static_cast<size_t>(x);
      const double g = dbl(gap_[i]);
      if (g < hi && bin_of(g) == static_cast<size_t>(j)) {
        in_bin_gap_[m] = gap_[i];
        in_bin_curv_[m] = curvature_[i];
        ++m;
      }
    }
  }
  double lo_d = edge(j), hi_d = edge(j + 1), d = lo_d;
  for (int it = 0; it < kMaxBisection; ++it) {
    d = 0.5 * (lo_d + hi_d);
    double c2 = cnt, g2 = sg, l2 = sc;
    for (size_t k = 0; k < m; ++k) {
      const double gk = dbl(in_bin_gap_[k]);
      if (gk < d) {
        c2 += 1;
        g2 += gk;
        l2 += dbl(in_bin_curv_[k]);
      }
    }
    const double f = kk * (d * c2 - g2) + kt * l2;
    if (std::fabs(f - target) < kForceRelTolerance * target) break;
    if (f < target)
      lo_d = d;
    else
      hi_d = d;
  }
  return d;
}

ContactSolution ContactSolver::indent(double press, float* u) const {
  ContactSolution s;
  s.press_mm = press;
  std::fill(u, u + gap_.size(), 0.0f);
  if (surface_.empty()) return s;
  const int32_t w = grid_.width, h = grid_.height;
  const auto d = static_cast<float>(press);
  const auto kappa = static_cast<float>(c_.kappa);
  const auto cap = static_cast<float>(c_.max_gel_mm);
  const auto layer_cap = static_cast<float>(c_.layer_cap_mm);
  const bool capped = cap_reached(press);
  double winkler = 0, tension = 0, sx = 0, sy = 0;
  float umax = 0;
  int32_t x0 = w, y0 = h, x1 = 0, y1 = 0;
  for (int32_t y = surface_.y0; y < surface_.y1; ++y) {
    const size_t row = static_cast<size_t>(y) * static_cast<size_t>(w);
    int64_t row_count = 0;
    double row_x = 0;
    for (int32_t x = surface_.x0; x < surface_.x1; ++x) {
      const float g = gap_[row + static_cast<size_t>(x)];
      if (!(g < d)) continue;
      float ug;
      if (capped) {  // force terms carry the gel's own share (contact.h)
        const float a = d - g;
        ug = std::min(std::max(kappa * a, a - layer_cap), cap);
        winkler += dbl(ug) / c_.kappa;
        tension += dbl(curvature_[row + static_cast<size_t>(x)]) * dbl(ug) / dbl(a) / c_.kappa;
      } else {
        ug = std::min(kappa * (d - g), cap);
        winkler += dbl(d - g);
        tension += dbl(curvature_[row + static_cast<size_t>(x)]);
      }
      u[row + static_cast<size_t>(x)] = ug;
      umax = std::max(umax, ug);
      x0 = std::min(x0, x);
      x1 = std::max(x1, x + 1);
      ++row_count;
      row_x += x;
    }
    if (row_count > 0) {
      y0 = std::min(y0, y);
      y1 = y + 1;
      s.pixels += row_count;
      sx += row_x;
      sy += static_cast<double>(y) * static_cast<double>(row_count);
    }
  }
  if (s.pixels == 0) return s;
  s.in_contact = true;
  s.force_n = c_.kappa * (c_.winkler * area_px_ * winkler + c_.tension * tension);
  s.max_gel_mm = dbl(umax);
  s.area_mm2 = static_cast<double>(s.pixels) * area_px_;
  const auto np = static_cast<double>(s.pixels);
  s.centroid_x_mm = (sx / np + 0.5 - 0.5 * w) * grid_.mm_per_px;
  s.centroid_y_mm = (sy / np + 0.5 - 0.5 * h) * grid_.mm_per_px;
  s.x0 = x0;
  s.y0 = y0;
  s.x1 = x1;
  s.y1 = y1;
  return s;
}

}  // namespace tlvlink::sim::internal
