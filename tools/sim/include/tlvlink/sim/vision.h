#pragma once
// The paired "vision" image of a touch sample: a camera-like picture of the object's surface,
// drawn from its class appearance (colour, pattern: grain, weave, speckle, bricks, blades,
// cells, ...) with a lighting gradient, vignetting and camera noise. Seeded: the same
// (material, appearance_seed, view, noise_seed, size) gives the same bytes.

#include <cstdint>

#include "tlvlink/error.h"
#include "tlvlink/sim/dataset.h"
#include "tlvlink/sim/materials.h"

namespace tlvlink::sim {

// Where the camera looks, per frame (the object stays the same within a session).
struct VisionView {
  double shift_x = 0, shift_y = 0;  // pattern offset, fraction of the shorter side [-10, 10]
  double zoom = 1.0;                // pattern scale [0.25, 4]
  double rotation_deg = 0;          // pattern rotation [-360, 360]
  double light_angle_deg = 45;      // direction of the brightness gradient
  double light_strength = 0.2;      // gradient amplitude (0 = flat lighting) [0, 0.8]
  double brightness = 1.0;          // exposure [0.3, 2]
  double noise_sigma_dn = 2.0;      // camera noise [0, 20]
};

// A plausible random view (small shifts and zoom, varied light) drawn from `seed`.
VisionView random_vision_view(uint64_t seed);

// Draws the image of `material` at height x width (each 1..8192) into `out` (reusing its
// buffer). `appearance_seed` fixes the object's pattern (knots, brick layout, ...).
// Errors: sizes out of range, view fields non-finite or out of range, unknown class id.
Status render_vision_image(const MaterialSample& material, uint64_t appearance_seed,
                           const VisionView& view, uint64_t noise_seed, int32_t height,
                           int32_t width, RgbImage& out);

}  // namespace tlvlink::sim
