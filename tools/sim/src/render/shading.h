#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "shading.h is internal to tools/sim: include its public headers instead"
#endif
// Photometric shading (gelsight-sim.md step 6): the colour change of a pixel whose gel surface
// normal tilts from n0 to n, under the sensor's coloured lights (diffuse + Phong specular).

#include <array>
#include <cstdint>

#include "render/blur.h"

namespace tlvlink::sim::internal {

struct LightModel {
  float lx = 0, ly = 0, lz = 1;  // unit vector towards the light
  std::array<float, 3> amp{};    // DN per unit of the shading term, per output channel
  float spec0 = 0;               // specular term of the flat gel, (l_z)^alpha
};

// Diffuse + specular term of one light for unit normal (nx, ny, nz): kd l.n + ks (r.v)^5,
// r = 2 (n.l) n - l, v = (0, 0, 1).
float shading_term(const LightModel& light, float nx, float ny, float nz);

// Diffuse + specular term for slopes (p, q) after the |grad z| <= 2.5 clamp.
float shading_term_for_slopes(const LightModel& light, float p, float q);

// Channel changes for surface slopes (p, q) = grad z relative to the rest slopes (p0, q0).
std::array<float, 3> shading_delta(const LightModel* lights, int32_t count, float p, float q,
                                   float p0, float q0);

struct ShadingInput {
  PlaneView z;             // surface displacement (mm) over the ROI, toward the object > 0
  int32_t x0 = 0, y0 = 0;  // ROI origin in the frame
  float mm_per_px = 0;
  const float* dome_p = nullptr;  // frame-sized rest slopes, or null for a flat gel
  const float* dome_q = nullptr;
  const float* const* dome_rest = nullptr;  // per light: frame-sized term of the rest normal
  int32_t frame_width = 0;
  const LightModel* lights = nullptr;
  int32_t light_count = 0;
};

// Writes the colour change of every ROI pixel into out[c] (frame-sized planes, row stride
// frame_width). `row_scratch` holds at least 6 * ROI width floats.
void shade_roi(const ShadingInput& in, std::array<float*, 3> out, float* row_scratch);

}  // namespace tlvlink::sim::internal
