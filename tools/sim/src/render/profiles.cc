// The built-in sensor profiles (gelsight-sensors.md, gelsight-sim.md). Values not given by the
// notes are our documented choices (tools/sim/REFERENCE.md, "Sensor profiles").
#include <array>

#include "tlvlink/sim/sensor.h"

namespace tlvlink::sim {
namespace {

constexpr std::array<std::string_view, 4> kNames = {"gelsight-mini", "digit", "digit-640x480",
                                                    "gelsight-r1.5"};

SensorProfile gelsight_mini() {
  SensorProfile p;  // the header's defaults are the Mini's
  p.name = "gelsight-mini";
  p.height = 240;
  p.width = 320;
  p.mm_per_px = 0.0634;  // at 320x240 after cropping the 3280x2464 frame's borders
  p.raw_height = 2464;
  p.raw_width = 3280;
  p.raw_format = "mjpeg";  // the only mode the camera offers
  p.raw_crop = 0.15;       // gsrobotics crops 15 % of each border before resizing to 320x240
  p.lights[0] = {90, {1, 0, 0}};
  p.lights[1] = {210, {0, 1, 0}};
  p.lights[2] = {330, {0, 0, 1}};
  p.light_count = 3;
  p.markers = true;  // 7x9 grid, 2.2 mm pitch (marker gels; a render decides whether to draw)
  return p;
}

// DIGIT: the camera's 320x240 (W x H) frames are stored transposed (and flipped top to bottom),
// portrait 240 wide x 320 high, as the DIGIT interface returns them. Thinner, slightly domed
// elastomer; TACTO's light layout.
SensorProfile digit(int32_t scale) {
  SensorProfile p;
  p.name = scale == 1 ? "digit" : "digit-640x480";
  p.height = 320 * scale;
  p.width = 240 * scale;
  p.mm_per_px = 0.04 / scale;
  p.raw_height = 240 * scale;
  p.raw_width = 320 * scale;
  p.raw_format = "yuyv";
  p.raw_transposed = true;  // digit_interface's get_frame: cv2.transpose, then cv2.flip(.., 0)
  p.gel_thickness_mm = 2.5;
  p.dome_sag_mm = 0.5;
  p.lights[0] = {30, {1, 0, 0}};
  p.lights[1] = {150, {0, 1, 0}};
  p.lights[2] = {270, {0, 0, 1}};
  p.light_count = 3;
  p.light_elevation = 0.35;
  p.background_rgb = {110, 125, 140};
  p.background_nonuniformity_dn = 20;
  p.vignetting = 0.3;
  p.markers = true;
  p.marker_rows = 8;
  p.marker_cols = 6;
  p.marker_pitch_mm = 1.6;
  p.marker_radius_mm = 0.2;
  p.noise_sigma_dn = 5;  // TACTO adds sigma 7 to a real background; DIGIT frames are noisier
  return p;
}

// GelSight R1.5 (Taxim's sensor): 240x320 at 0.06 mm/px (documented range 0.03-0.09 by crop),
// three coloured lights plus a white one.
SensorProfile gelsight_r15() {
  SensorProfile p;
  p.name = "gelsight-r1.5";
  p.height = 240;
  p.width = 320;
  p.mm_per_px = 0.06;
  p.raw_height = 240;
  p.raw_width = 320;
  p.raw_format = "mjpeg";  // HTTP MJPEG stream from the internal Pi
  p.lights[0] = {90, {1, 0, 0}};
  p.lights[1] = {210, {0, 1, 0}};
  p.lights[2] = {330, {0, 0, 1}};
  p.lights[3] = {30, {0.35, 0.35, 0.35}};
  p.light_count = 4;
  p.background_rgb = {140, 135, 130};
  p.background_nonuniformity_dn = 25;  // older LEDs: offsets up to +-27 DN in Taxim's data
  p.vignetting = 0.2;
  p.markers = true;
  p.marker_rows = 7;
  p.marker_cols = 9;
  p.marker_pitch_mm = 2.0;
  p.noise_sigma_dn = 2;
  return p;
}

}  // namespace

std::span<const std::string_view> sensor_profile_names() { return kNames; }

Result<SensorProfile> sensor_profile(std::string_view name) {
  if (name == "gelsight-mini") return gelsight_mini();
  if (name == "digit") return digit(1);
  if (name == "digit-640x480") return digit(2);
  if (name == "gelsight-r1.5") return gelsight_r15();
  return Error::make(ErrorCode::kInvalidArgument,
                     "unknown sensor profile \"%.*s\" (known: gelsight-mini, digit, "
                     "digit-640x480, gelsight-r1.5)",
                     static_cast<int>(name.size()), name.data());
}

}  // namespace tlvlink::sim
