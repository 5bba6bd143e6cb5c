#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "sensor_tables.h is internal to tools/sim: include its public headers instead"
#endif
// Everything about one sensor instance that does not change from frame to frame, computed once
// in Renderer::create: pixel grid, background, vignetting, gains, dome, lights, marker grid.
// The per-instance variation (illumination polynomial, LED and white-balance gains) is drawn
// from sensor_seed, so a seed is a physical sensor.

#include <array>
#include <cstdint>
#include <vector>

#include "render/blur.h"
#include "render/shading.h"
#include "tlvlink/sim/sensor.h"

namespace tlvlink::sim::internal {

// Pixel (x, y) has its centre at (x_mm(x), y_mm(y)) from the gel centre; y points down.
struct FrameGrid {
  int32_t height = 0, width = 0;
  double mm_per_px = 0;
  double x_mm(int32_t x) const { return (x + 0.5 - 0.5 * width) * mm_per_px; }
  double y_mm(int32_t y) const { return (y + 0.5 - 0.5 * height) * mm_per_px; }
  size_t pixels() const { return static_cast<size_t>(height) * static_cast<size_t>(width); }
};

// A rectangle of the frame, [x0, x1) x [y0, y1).
struct Roi {
  int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int32_t width() const { return x1 - x0; }
  int32_t height() const { return y1 - y0; }
  bool empty() const { return x1 <= x0 || y1 <= y0; }
};

// Pixels rendered beyond the processed frame on each side (x: left and right, y: top and
// bottom). The raw camera path (tools/sim/src/raw) renders the periphery the processed crop cuts
// away; the processed frame stays the reference for every normalisation (illumination polynomial
// and its amplitude, vignetting radius, dome, texture statistics, marker grid), extended
// outward, so the centre of a padded grid matches the plain one.
struct Periphery {
  int32_t x = 0, y = 0;
};

struct SensorTables {
  SensorTables() = default;
  SensorTables(SensorTables&&) = default;  // moving keeps dome_rest_ptr valid, copying would not
  SensorTables& operator=(SensorTables&&) = default;
  SensorTables(const SensorTables&) = delete;
  SensorTables& operator=(const SensorTables&) = delete;

  FrameGrid grid;  // the processed frame plus the periphery
  Roi view;        // the processed frame inside `grid`
  // Illumination b_c (1 + poly) in DN, before the camera blur, gain and vignetting (planar).
  std::array<std::vector<float>, 3> background_raw;
  // The camera's no-contact output at led_gain 1, before noise: vignetting * gain * blur(raw).
  std::array<std::vector<float>, 3> background_final;
  std::vector<float> vignetting;  // max(0, 1 - k_v r^2), r = 1 at a corner of the processed frame
  std::array<float, 3> gain{};    // profile channel gain x per-sensor white balance x exposure
  // Dome (rest surface height toward the object, and its slopes); empty for a flat gel.
  std::vector<float> dome_height, dome_p, dome_q;
  std::array<std::vector<float>, 4> dome_rest;  // per light: shading term of the rest normal
  std::array<const float*, 4> dome_rest_ptr{};
  std::array<LightModel, 4> lights{};
  int32_t light_count = 0;
  float light_scale = 0;  // the DN scale that puts the 45 deg response at kMaxDeltaAt45Dn
  // Row-major grid from the gel centre; with a periphery, extended by whole pitches on each
  // side to fill it (the profile's grid stays where it is).
  std::vector<std::array<double, 2>> marker_rest_mm;
  std::vector<uint8_t> background_u8;  // interleaved RGB
};

// `blur` provides scratch for the camera blur of the background (sized for the padded grid).
SensorTables build_sensor_tables(const SensorProfile& profile, uint64_t sensor_seed,
                                 GaussianBlur& blur, Periphery periphery = {});

// Light vectors and per-channel amplitudes (before per-sensor gains) and the scale that makes
// the strongest channel change at a 45 deg tilt equal to kMaxDeltaAt45Dn.
void build_lights(const SensorProfile& profile, std::array<LightModel, 4>& lights, float& scale);

}  // namespace tlvlink::sim::internal
