#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "contact_area.h is internal to tools/sim: include its public headers instead"
#endif
// A coarse, fast version of the renderer's contact mechanics (gelsight-sim.md, STATIC FRAME
// steps 1-3: gap, compliance split, Winkler layer plus membrane tension, bisection on the press
// depth; constants shared with the renderer through
// tools/sim/src/render/model_constants.h) that returns only the contact
// area. The grasp rule and its oracle need the area of thousands of
// hypothetical grasps, far too many to render.

#include "../render/model_constants.h"
#include "tlvlink/sim/scene.h"

namespace tlvlink::sim::internal {

// The gel parameters the model needs (from a SensorProfile; defaults: GelSight Mini).
struct GelContactModel {
  double height_mm = 240 * 0.0634, width_mm = 320 * 0.0634;  // imaged gel area
  double gel_thickness_mm = 4.0;
  double gel_modulus_pa = 150e3;
  double gel_poisson = 0.485;
  // The renderer's fitted force model (Taxim R1.5 table): Winkler confinement chi, membrane
  // tension psi, tension slope cap. A test checks the areas against rendered frames.
  double confinement = kChi;
  double tension = kPsi;
  double tension_max_slope = kTensionMaxSlope;
  int32_t grid_rows = 48, grid_cols = 64;
};

// Compliance split kappa = C_g t_g / (C_g t_g + C_o L_o), C = (1 - nu^2) / E, in (0, 1].
double compliance_split(const GelContactModel& gel, const ObjectMechanics& mechanics);

// Contact area (mm^2) of `geometry` pressed into the gel with `force_n`; 0 for no object or no
// force. The press depth is clamped so the gel indentation stays <= 0.9 t_g, as in the renderer.
double contact_area_mm2(const GelContactModel& gel, const ObjectGeometry& geometry,
                        const ObjectMechanics& mechanics, double force_n);

}  // namespace tlvlink::sim::internal
