#include "render/shear.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "render/model_constants.h"

namespace tlvlink::sim::internal {
namespace {

// num / den, saturating at kSlipRatioCap; 0 / 0 = 0 (no load, no slip).
double ratio(double num, double den) {
  if (den > 1e-15) return std::min(num / den, kSlipRatioCap);
  return num > 0 ? kSlipRatioCap : 0.0;
}

std::array<double, 2> rigid(const ShearField& f, double px, double py) {
  const double c = std::cos(f.twist_rad) - 1, s = std::sin(f.twist_rad);
  return {f.shift_x_mm + c * px - s * py, f.shift_y_mm + s * px + c * py};
}

}  // namespace

ShearField solve_shear(const SensorProfile& sensor, const Loading& l, const ContactSolution& k) {
  ShearField f;
  if (!k.in_contact || !(k.force_n > 0)) return f;
  f.active = true;
  f.center_x_mm = k.centroid_x_mm;
  f.center_y_mm = k.centroid_y_mm;
  const double a = std::sqrt(k.area_mm2 / std::numbers::pi);
  f.contact_radius_mm = a;
  const double nu = sensor.gel_poisson, t = sensor.gel_thickness_mm;
  const double g = sensor.gel_modulus_pa * 1e-6 / (2 * (1 + nu));  // N/mm^2
  // Half-space vs thin-layer tangential stiffness (heuristic max), torsional stiffness; floors
  // keep a point contact finite.
  const double kt =
      std::max({8 * a * g / (2 - nu), g * std::numbers::pi * a * a / t, kStiffnessFloor});
  const double ktheta = std::max(16.0 / 3.0 * g * a * a * a, kStiffnessFloor);
  const double q = std::hypot(l.shear_x_n, l.shear_y_n);
  const double m = std::fabs(l.torque_nmm);
  const double limit = l.friction * k.force_n;
  f.rho_translation = ratio(q, limit);
  f.rho_torsion = ratio(m, 3 * std::numbers::pi / 16 * limit * a);
  f.rho = std::min(std::hypot(f.rho_translation, f.rho_torsion), kSlipRatioCap);
  f.gross_slip = f.rho >= 1;
  double sx, sy, twist;
  if (!f.gross_slip) {
    f.stick_radius_mm = a * std::cbrt(1 - f.rho);
    sx = l.shear_x_n / kt;
    sy = l.shear_y_n / kt;
    twist = l.torque_nmm / ktheta;
  } else {  // sliding: the drag saturates at the friction limit
    f.stick_radius_mm = 0;
    sx = q > 0 ? l.shear_x_n / q * limit / kt : 0;
    sy = q > 0 ? l.shear_y_n / q * limit / kt : 0;
    twist = m > 0 ? std::copysign(3 * std::numbers::pi / 16 * limit * a / ktheta, l.torque_nmm) : 0;
  }
  // The gel cannot shear without bound: cap the rigid shift and twist (heuristic).
  const double max_shift = kMaxShearStrain * t, shift = std::hypot(sx, sy);
  if (shift > max_shift) {
    sx *= max_shift / shift;
    sy *= max_shift / shift;
  }
  f.shift_x_mm = sx;
  f.shift_y_mm = sy;
  f.twist_rad = std::clamp(twist, -kMaxTwistRad, kMaxTwistRad);
  return f;
}

std::array<double, 2> shear_displacement(const ShearField& f, double x_mm, double y_mm) {
  if (!f.active) return {0, 0};
  const double px = x_mm - f.center_x_mm, py = y_mm - f.center_y_mm;
  const double r = std::hypot(px, py), a = f.contact_radius_mm, c = f.stick_radius_mm;
  if (r <= c) return rigid(f, px, py);
  if (r <= a) {  // slip annulus lags the stick region
    const double u = (r - c) / (a - c);
    const double k = 1 - kAnnulusLag * u * u;
    const auto d = rigid(f, px, py);
    return {d[0] * k, d[1] * k};
  }
  // Outside: the boundary value in this direction, decaying.
  const double edge = a > c ? 1 - kAnnulusLag : 1.0;
  const double k = edge * std::exp(-kShearLambdaPerMm2 * (r - a) * (r - a));
  const auto d = rigid(f, px * a / r, py * a / r);
  return {d[0] * k, d[1] * k};
}

std::array<double, 2> slip_direction(const Loading& l) {
  const double q = std::hypot(l.shear_x_n, l.shear_y_n);
  if (q > 0) return {l.shear_x_n / q, l.shear_y_n / q};
  return {0, 1};
}

MarkerShearStats marker_shear_stats(const ShearField& f,
                                    std::span<const std::array<double, 2>> rest,
                                    std::array<double, 2> slip) {
  MarkerShearStats s;
  if (!f.active || rest.empty()) return s;
  double total = 0;
  for (const auto& p : rest) {
    const auto d = shear_displacement(f, p[0], p[1]);
    total += std::hypot(d[0], d[1]);
    const double px = p[0] - f.center_x_mm, py = p[1] - f.center_y_mm;
    if (std::hypot(px, py) > f.contact_radius_mm) continue;
    const auto r = rigid(f, px, py);
    if (std::hypot(d[0] - r[0] - slip[0], d[1] - r[1] - slip[1]) > kDeviationMm) ++s.deviating;
  }
  s.mean_shear_mm = total / static_cast<double>(rest.size());
  return s;
}

}  // namespace tlvlink::sim::internal
