// Object heights are evaluated at cell centres of a coarse grid over the imaged gel. The force of
// a press depth delta is kappa * (k_w * sum max(0, delta - gap) * cell + T * sum curvature) over
// the cells in contact, with the Winkler stiffness k_w = chi E_g / ((1 - nu_g^2) t_g), the
// membrane tension T = psi E_g t_g / (6 (1 + nu_g)) and the curvature of a cell the sum of its
// (clamped) height excess over its four neighbours -- grid independent, as in the renderer.
// delta is found by bisection.

#include "gen/contact_area.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace tlvlink::sim::internal {
namespace {

constexpr double kMinCompliance = 1e-15;  // 1/Pa; keeps kappa defined for rigid objects
constexpr int kBisectionSteps = 60;
constexpr double kForceTolerance = 1e-3;  // relative
constexpr double kFar = -1e9;             // "height" of cells the object does not reach
constexpr double kEdgeDropMm = 10.0;      // a ball beyond its equator / a box beyond its edge

// Height (mm, higher = closer to the gel) of the object's surface above gel point (x, y).
double object_height(const ObjectGeometry& g, double x, double y) {
  const double dx = x - g.center_x_mm, dy = y - g.center_y_mm;
  const double angle = g.angle_deg * std::numbers::pi / 180.0;
  const double ca = std::cos(angle), sa = std::sin(angle);
  switch (g.shape) {
    case Shape::kNone: return kFar;
    case Shape::kFlatPlate:
    case Shape::kHeightMap: return 0;  // height maps: treated as flat here (not used by grasps)
    case Shape::kSphere:
    case Shape::kPoint: {
      const double r = std::max(g.radius_mm, 1e-6);
      const double d2 = dx * dx + dy * dy;
      return d2 < r * r ? -d2 / (std::sqrt(r * r - d2) + r) : -r - kEdgeDropMm;
    }
    case Shape::kCylinder: {
      const double r = std::max(g.radius_mm, 1e-6);
      const double along = dx * ca + dy * sa, across = -dx * sa + dy * ca;
      const double beyond = std::max(0.0, std::fabs(along) - g.length_mm * 0.5);  // a capsule
      const double d2 = across * across + beyond * beyond;
      return d2 < r * r ? -d2 / (std::sqrt(r * r - d2) + r) : -r - kEdgeDropMm;
    }
    case Shape::kBoxEdge: {
      const double across = -dx * sa + dy * ca;  // the box occupies across <= 0
      return across <= 0 ? 0 : -kEdgeDropMm;
    }
  }
  return kFar;
}

}  // namespace

double compliance_split(const GelContactModel& gel, const ObjectMechanics& m) {
  const double cg =
      std::max((1 - gel.gel_poisson * gel.gel_poisson) / gel.gel_modulus_pa, kMinCompliance);
  const double co = std::max((1 - m.poisson * m.poisson) / m.modulus_pa, kMinCompliance);
  const double gel_term = cg * gel.gel_thickness_mm;
  return gel_term / (gel_term + co * std::max(m.local_radius_mm, 0.0));
}

double contact_area_mm2(const GelContactModel& gel, const ObjectGeometry& geometry,
                        const ObjectMechanics& mechanics, double force_n) {
  if (!(force_n > 0) || geometry.shape == Shape::kNone) return 0;
  const int32_t rows = std::max(gel.grid_rows, 1), cols = std::max(gel.grid_cols, 1);
  const double ch = gel.height_mm / rows, cw = gel.width_mm / cols, cell = ch * cw;
  std::vector<double> height(static_cast<size_t>(rows) * static_cast<size_t>(cols));
  double top = kFar;
  for (int32_t r = 0; r < rows; ++r) {
    for (int32_t c = 0; c < cols; ++c) {
      const double y = (r + 0.5) * ch - gel.height_mm * 0.5,
                   x = (c + 0.5) * cw - gel.width_mm * 0.5;
      const double h = object_height(geometry, x, y);
      height[static_cast<size_t>(r) * static_cast<size_t>(cols) + static_cast<size_t>(c)] = h;
      top = std::max(top, h);
    }
  }
  if (top <= kFar) return 0;  // the object misses the gel
  // Membrane curvature term per cell.
  std::vector<double> curvature(height.size(), 0.0);
  const double cap_y = gel.tension_max_slope * ch, cap_x = gel.tension_max_slope * cw;
  auto at = [&](int32_t r, int32_t c) {
    r = std::clamp(r, 0, rows - 1);
    c = std::clamp(c, 0, cols - 1);
    return height[static_cast<size_t>(r) * static_cast<size_t>(cols) + static_cast<size_t>(c)];
  };
  for (int32_t r = 0; r < rows; ++r) {
    for (int32_t c = 0; c < cols; ++c) {
      const double h = at(r, c);
      const double s = std::clamp(h - at(r, c - 1), -cap_x, cap_x) +
                       std::clamp(h - at(r, c + 1), -cap_x, cap_x) +
                       std::clamp(h - at(r - 1, c), -cap_y, cap_y) +
                       std::clamp(h - at(r + 1, c), -cap_y, cap_y);
      curvature[static_cast<size_t>(r) * static_cast<size_t>(cols) + static_cast<size_t>(c)] =
          std::max(0.0, s);
    }
  }
  const double kappa = compliance_split(gel, mechanics);
  // A compliant layer bottoms out as in the renderer (render/contact.h): each cell's gel share
  // of its approach a is max(kappa a, a - cap) once the cap can be reached.
  const double layer_cap = mechanics.layer_mm > 0 ? kMaxLayerStrain * mechanics.layer_mm : 0;
  const double gel_max = kMaxGelStrain * gel.gel_thickness_mm;
  const bool capped = layer_cap > 0 && layer_cap / std::max(1 - kappa, 1e-300) < gel_max / kappa;
  const double e_gel = gel.gel_modulus_pa * 1e-6;  // N/mm^2
  const double k =
      gel.confinement * e_gel / ((1 - gel.gel_poisson * gel.gel_poisson) * gel.gel_thickness_mm);
  const double t = gel.tension * e_gel * gel.gel_thickness_mm / (6 * (1 + gel.gel_poisson));
  auto force_at = [&](double depth) {
    // Below the depth where the layer reaches its cap, F is the uncapped one (same arithmetic as
    // before the cap existed).
    const bool reached = capped && (1 - kappa) * depth > layer_cap;
    double w = 0, c = 0;
    for (size_t i = 0; i < height.size(); ++i) {
      const double gap = top - height[i];
      if (gap < depth) {
        if (reached) {
          const double a = depth - gap;
          const double share = std::min(std::max(kappa * a, a - layer_cap), gel_max) / a;
          w += share * a;
          c += share * curvature[i];
        } else {
          w += depth - gap;
          c += curvature[i];
        }
      }
    }
    return reached ? k * w * cell + t * c : kappa * (k * w * cell + t * c);
  };
  double lo = 0, hi = gel_max / kappa;
  double delta = hi;  // the depth limit when even it does not reach the force
  if (force_at(hi) > force_n) {
    for (int i = 0; i < kBisectionSteps; ++i) {
      delta = 0.5 * (lo + hi);
      const double f = force_at(delta);
      if (std::fabs(f - force_n) < kForceTolerance * force_n) break;  // as the renderer
      (f < force_n ? lo : hi) = delta;
    }
  }
  int64_t touching = 0;
  for (double h : height) touching += top - h < delta ? 1 : 0;
  return static_cast<double>(touching) * cell;
}

}  // namespace tlvlink::sim::internal
