#pragma once
// Sensor profiles for the GelSight simulator: geometry, gel, lights, background and camera
// artefacts of each supported sensor. Every field has a documented default and range
// (tools/sim/REFERENCE.md); validate() rejects out-of-range or non-finite values by name.

#include <array>
#include <cstdint>
#include <span>
#include <string_view>

#include "tlvlink/error.h"

namespace tlvlink::sim {

struct Light {
  // Direction in the image plane, from +x (right) toward +y (down).
  double azimuth_deg = 90.0;              // [0, 360)
  std::array<double, 3> rgb = {1, 0, 0};  // colour, each in [0, 2]

  bool operator==(const Light&) const = default;
};

struct SensorProfile {
  std::string_view name = "gelsight-mini";
  // Processed frame the simulator renders (what a dataset stores).
  int32_t height = 240, width = 320;  // [16, 4096]
  double mm_per_px = 0.0634;          // [0.01, 0.5]
  // What the physical camera emits before cropping/resizing (RawCamera in raw_camera.h renders
  // it): e.g. the Mini's MJPEG 3280x2464. 0 = the processed size (in the camera's orientation).
  int32_t raw_height = 0, raw_width = 0;
  std::string_view raw_format = "rgb";  // "rgb", "mjpeg", "yuyv"
  // The processed frame is the raw frame with raw_crop of each border cut away, resized; the
  // Mini: 0.15. raw_transposed: the processed frame is the raw one transposed and then flipped
  // top to bottom (what DIGIT's Python interface returns).
  double raw_crop = 0;  // [0, 0.45]
  bool raw_transposed = false;
  // Gel.
  double gel_thickness_mm = 4.0;  // [0.5, 10]
  double gel_modulus_pa = 150e3;  // [1e3, 1e8]
  double gel_poisson = 0.485;     // [0, 0.499]
  double dome_sag_mm = 0.0;       // [0, 2] (0 = flat gel)
  // Lights (3 or 4) at elevation vector (cos phi, sin phi, light_elevation) normalised.
  std::array<Light, 4> lights{};
  int32_t light_count = 3;        // [1, 4]
  double light_elevation = 0.25;  // [0.05, 5]
  // Background: per-channel base level (DN), low-order illumination polynomial, vignetting.
  std::array<double, 3> background_rgb = {120, 130, 125};  // each [0, 255]
  double background_nonuniformity_dn = 15.0;  // [0, 40] amplitude of the low-order terms
  double vignetting = 0.25;                   // [0, 0.9] k_v in (1 - k_v r^2), r = 1 at a corner
  // Markers (optional on a profile; a render can switch them off).
  bool markers = false;
  int32_t marker_rows = 7, marker_cols = 9;  // [1, 64]
  double marker_pitch_mm = 2.2;              // [0.3, 10]
  double marker_radius_mm = 0.25;            // [0.05, 1]
  // Camera.
  double noise_sigma_dn = 3.0;                     // [0, 20]
  std::array<double, 3> channel_gain = {1, 1, 1};  // white balance, each [0.5, 2]

  bool operator==(const SensorProfile&) const = default;
};

// Names: "gelsight-mini" (240x320 processed, 0.0634 mm/px; the camera emits MJPEG 3280x2464),
// "digit" (camera 320x240 YUYV, stored transposed and flipped top to bottom: 240 wide x 320
// high, 0.04 mm/px),
// "digit-640x480" (480 wide x 640 high, 0.02 mm/px), "gelsight-r1.5" (240x320, 0.06 mm/px).
// Values and their sources: tools/sim/REFERENCE.md, "Sensor profiles".
std::span<const std::string_view> sensor_profile_names();
Result<SensorProfile> sensor_profile(std::string_view name);
// Checks every field against its documented range; the error names the field and the value.
Status validate(const SensorProfile& profile);

}  // namespace tlvlink::sim
