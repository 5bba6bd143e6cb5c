#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "texture.h is internal to tools/sim: include its public headers instead"
#endif
// Fractal surface texture (gelsight-sim.md step 1): fractional-Brownian value noise. Octave k has
// lattice spacing correlation_length / 2^k and amplitude 2^(-k H) (self-affine with Hurst
// exponent H), down to 2 px; lattice values are a hash of (seed, octave, cell), interpolated with
// smoothstep weights, so the texture is fixed to the object (it moves with it) and costs a few
// flops per pixel and octave. The sum is made zero-mean with RMS sq over the frame.

#include <cstdint>
#include <vector>

#include "render/sensor_tables.h"
#include "tlvlink/sim/scene.h"

namespace tlvlink::sim::internal {

class FractalTexture {
 public:
  // Scratch for a grid of this size (the only allocation).
  explicit FractalTexture(const FrameGrid& grid);

  // Adds the texture of `t` (object origin at (origin_x_mm, origin_y_mm) from the gel centre)
  // to h (mm) inside `roi` (the object's surface), zero-mean with RMS sq over roi ∩ `stats`
  // (all of roi when `stats` is empty or misses it: a renderer with a periphery passes the
  // processed view, so its centre gets the texture a plain renderer draws). Nothing happens for
  // sq_um == 0.
  void add(const SurfaceTexture& t, double origin_x_mm, double origin_y_mm, Roi roi, float* h,
           Roi stats = {});

  // The last texture added (mm) over the last roi, row stride roi width; for tests.
  const std::vector<float>& last() const { return tex_; }

 private:
  FrameGrid grid_;
  std::vector<float> tex_;
  std::vector<int32_t> cell_x_;               // lattice cell of each column (relative to the first)
  std::vector<float> weight_x_;               // smoothstep weight of each column
  std::vector<float> lattice_a_, lattice_b_;  // lattice rows iy and iy + 1, y-interpolated row
  std::vector<float> row_;
};

}  // namespace tlvlink::sim::internal
