#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "view_optics.h is internal to tools/trainer: include its public headers instead"
#endif
// The sensor-view augmentation's image operations on a float RGB frame (view_augment.h): each
// takes its parameters already drawn, so tests can call them with fixed values. No allocation
// except where a scratch vector is passed in and grown once.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tlvlink::trainer::view {

struct Affine {
  double scale = 1, rotation_rad = 0, shift_x = 0, shift_y = 0;  // shifts in pixels
};
// dst = src seen by a camera mounted with `a` (about the frame centre), bilinear, edges repeated.
void warp(const float* src, float* dst, int32_t width, int32_t height, const Affine& a);

// Per-channel gain and offset (DN) times a radial vignette (1 - k r^2, r the distance from
// (cx, cy) over the half diagonal) and a per-channel linear LED gradient (1 + drift[c] t, t in
// [-1, 1] along `drift_angle_rad`), in place.
struct Shading {
  float gain[3] = {1, 1, 1}, offset[3] = {0, 0, 0};
  double vignette = 0, vignette_cx = 0.5, vignette_cy = 0.5;  // centre as a fraction of the frame
  float drift[3] = {0, 0, 0};
  double drift_angle_rad = 0;
};
void shade(float* frame, int32_t width, int32_t height, const Shading& s);

// A soft dark speck: the frame scaled by 1 - darkness * exp(-d^2 / (2 radius^2)), in place.
struct Speck {
  double x = 0, y = 0, radius = 1, darkness = 0.3;
};
void darken(float* frame, int32_t width, int32_t height, const Speck& speck);

// Separable Gaussian blur of standard deviation sigma (pixels), edges repeated, in place.
void blur(float* frame, int32_t width, int32_t height, double sigma, std::vector<float>& scratch);

// Adds approximately normal noise of `sigma` DN to every value, drawn from `seed`, in place.
void add_noise(float* frame, size_t values, double sigma, uint64_t seed);

// Rounds to uint8 (half away from zero), clamped.
void to_uint8(const float* frame, uint8_t* out, size_t values);

}  // namespace tlvlink::trainer::view
