#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "vision_noise.h is internal to tools/sim: include its public headers instead"
#endif
// Procedural noise for the vision images: hashed-lattice value noise, fractal sums of it, and
// cellular (Worley) distances. Pure functions of (position, seed): no tables, no state.

#include <cmath>
#include <cstdint>

#include "gen/rng.h"

namespace tlvlink::sim::internal {

// Uniform [0, 1) value attached to integer lattice point (x, y) under `seed`.
inline double lattice_value(int64_t x, int64_t y, uint64_t seed) {
  const uint64_t h = mix64(seed ^ (static_cast<uint64_t>(x) * 0x9E3779B97F4A7C15ull) ^
                           (static_cast<uint64_t>(y) * 0xC2B2AE3D27D4EB4Full));
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

inline double smooth01(double t) { return t * t * (3.0 - 2.0 * t); }

// Smooth value noise in [0, 1), one lattice cell per unit.
inline double value_noise(double x, double y, uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
  const double tx = smooth01(x - fx), ty = smooth01(y - fy);
  const double a = lattice_value(ix, iy, seed), b = lattice_value(ix + 1, iy, seed);
  const double c = lattice_value(ix, iy + 1, seed), d = lattice_value(ix + 1, iy + 1, seed);
  return (a + (b - a) * tx) + ((c + (d - c) * tx) - (a + (b - a) * tx)) * ty;
}

// Fractal sum of `octaves` value-noise layers (each twice the frequency, half the amplitude),
// normalised to [0, 1).
inline double fbm(double x, double y, uint64_t seed, int octaves) {
  double sum = 0, amplitude = 1, norm = 0;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * value_noise(x, y, seed + static_cast<uint64_t>(o) * 0x51ED27ull);
    norm += amplitude;
    amplitude *= 0.5;
    x *= 2.0;
    y *= 2.0;
  }
  return sum / norm;
}

// Distances to the nearest and second-nearest jittered cell point, and the nearest cell's id.
struct Cell {
  double d1 = 1e9, d2 = 1e9;
  uint64_t id = 0;
};

inline Cell worley(double x, double y, uint64_t seed) {
  const auto ix = static_cast<int64_t>(std::floor(x)), iy = static_cast<int64_t>(std::floor(y));
  Cell cell;
  for (int64_t j = iy - 1; j <= iy + 1; ++j) {
    for (int64_t i = ix - 1; i <= ix + 1; ++i) {
      const double px = static_cast<double>(i) + lattice_value(i, j, seed);
      const double py = static_cast<double>(j) + lattice_value(i, j, seed ^ 0xABCDEFull);
      const double d = (px - x) * (px - x) + (py - y) * (py - y);  // squared until the end
      if (d < cell.d1) {
        cell.d2 = cell.d1;
        cell.d1 = d;
        cell.id =
            mix64(static_cast<uint64_t>(i) * 0x632BE59BD9B4E019ull ^ static_cast<uint64_t>(j));
      } else if (d < cell.d2) {
        cell.d2 = d;
      }
    }
  }
  cell.d1 = std::sqrt(cell.d1);
  cell.d2 = std::sqrt(cell.d2);
  return cell;
}

// Uniform [0, 1) from an id (e.g. a cell or a brick).
inline double unit_hash(uint64_t id, uint64_t seed) {
  return static_cast<double>(mix64(id ^ mix64(seed)) >> 11) * 0x1.0p-53;
}

}  // namespace tlvlink::sim::internal
