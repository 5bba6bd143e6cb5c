#pragma once
// The physical state of a contact: what the simulator's renderer reports with every frame and the
// datasets store beside it (tlvlink/datasets/records.h). Plain data; real recordings leave it 0.

#include <cstdint>

namespace tlvlink::touch {

// Physical state of the contact, reported with every frame (all finite; 0 when undefined).
struct ContactState {
  bool in_contact = false;
  double force_n = 0;   // normal load actually applied
  double press_mm = 0;  // total approach delta
  double max_gel_indentation_mm = 0;
  double kappa = 0;          // compliance split: share of the approach taken by the gel
  double texture_kappa = 0;  // the same for the object's texture, at its own scale
  double contact_area_mm2 = 0;
  double contact_radius_mm = 0;  // a = sqrt(area / pi)
  double stick_radius_mm = 0;    // c (Cattaneo-Mindlin), 0 in gross slip
  double slip_ratio = 0;         // rho (limit-surface), 0 without contact
  bool gross_slip = false;       // rho >= 1
  // Markers inside the contact more than 0.25 mm off the stick region's rigid motion (plus the
  // object's travel in gross slip): the incipient-slip cue (Dong 2019: > 3 markers > 4 px).
  // Counted on the profile's marker grid whether or not markers are drawn.
  int32_t markers_deviating = 0;
  double mean_shear_mm = 0;  // mean |shear displacement| over the marker grid
};

}  // namespace tlvlink::touch
