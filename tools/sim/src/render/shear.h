#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "shear.h is internal to tools/sim: include its public headers instead"
#endif
// Tangential contact (gelsight-sim.md MARKERS/SHEAR): limit-surface slip ratio rho, the
// Cattaneo-Mindlin stick radius c = a (1 - rho)^(1/3), the rigid shift and twist of the stick
// region, the lagging slip annulus, the decay outside the contact, and gross slip (rho >= 1).

#include <array>
#include <cstdint>
#include <span>

#include "render/contact.h"
#include "tlvlink/sim/scene.h"
#include "tlvlink/sim/sensor.h"

namespace tlvlink::sim::internal {

struct ShearField {
  bool active = false;  // in contact with a positive normal load
  double center_x_mm = 0, center_y_mm = 0;
  double contact_radius_mm = 0;           // a = sqrt(area / pi)
  double stick_radius_mm = 0;             // c, 0 in gross slip
  double shift_x_mm = 0, shift_y_mm = 0;  // rigid shift of the stick region
  double twist_rad = 0;
  double rho = 0, rho_translation = 0, rho_torsion = 0;
  bool gross_slip = false;
};

ShearField solve_shear(const SensorProfile& sensor, const Loading& loading,
                       const ContactSolution& contact);

// Shear displacement (mm) of the gel surface point at (x, y) mm from the gel centre.
std::array<double, 2> shear_displacement(const ShearField& field, double x_mm, double y_mm);

// Direction of gross-slip travel: along the tangential load, or +y (gravity) without one.
std::array<double, 2> slip_direction(const Loading& loading);

struct MarkerShearStats {
  int32_t deviating = 0;     // markers in the contact > kDeviationMm off the rigid motion
  double mean_shear_mm = 0;  // mean |shear displacement| over the grid
};

// Statistics of the shear field sampled at the rest marker grid. The rigid motion is that of
// the stick region (what a robust rigid fit to the markers recovers), plus the object's travel
// `slip_mm_xy` in gross slip: markers that lag it are the incipient- or gross-slip cue.
MarkerShearStats marker_shear_stats(const ShearField& field,
                                    std::span<const std::array<double, 2>> rest_mm,
                                    std::array<double, 2> slip_mm_xy);

}  // namespace tlvlink::sim::internal
