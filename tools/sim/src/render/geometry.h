#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "geometry.h is internal to tools/sim: include its public headers instead"
#endif
// Object surface height maps (mm, positive toward the gel; analytic shapes have their highest
// point at 0) and the membrane-tension curvature term of the contact force.

#include "render/sensor_tables.h"
#include "tlvlink/sim/scene.h"

namespace tlvlink::sim::internal {

// Where the object is in this frame: its centre (mm from the gel centre) and in-plane rotation.
// Gross slip moves and turns it relative to the gel.
struct Placement {
  double center_x_mm = 0, center_y_mm = 0;
  double angle_deg = 0;
};

// Fills h (grid.pixels() floats). kNone is not drawn (caller's job). kHeightMap is shifted by
// whole pixels (nearest-pixel translation, edges repeated).
void object_height(const ObjectGeometry& geometry, const Placement& at, const FrameGrid& grid,
                   float* h);

// Bounding box of the pixels where the object has a surface (h above -kSurfaceGapLimitMm);
// empty if none. Everything outside it can never touch.
Roi surface_bounds(const float* h, const FrameGrid& grid);

// Membrane term per pixel (mm): the positive part of the 5-point sum of gap differences
// sum_n (g_n - g) of surface `h0` (g = max h - h), each difference clamped to
// +-kTensionMaxSlope * pixel, so a sharp step pulls with a bounded share of the tension.
// Summed over the contact and multiplied by the tension it gives the membrane force.
// Computed inside `roi` only.
void tension_curvature(const float* h0, const FrameGrid& grid, Roi roi, float* curvature);

}  // namespace tlvlink::sim::internal
