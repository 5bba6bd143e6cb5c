// Parameter sets that must be rejected: every floating-point field of the sensor profile, scene
// and render options set to NaN, +Inf and -Inf in turn, plus a few out-of-range values. Each
// case names the field its error must mention.
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "tlvlink/sim/extreme.h"

namespace tlvlink::sim {
namespace {

struct Field {
  std::string_view name;
  std::function<void(InvalidCase&, double)> set;
};

std::vector<Field> fields() {
  using C = InvalidCase;
  return {
      {"sensor.mm_per_px", [](C& c, double v) { c.sensor.mm_per_px = v; }},
      {"sensor.raw_crop", [](C& c, double v) { c.sensor.raw_crop = v; }},
      {"sensor.gel_thickness_mm", [](C& c, double v) { c.sensor.gel_thickness_mm = v; }},
      {"sensor.gel_modulus_pa", [](C& c, double v) { c.sensor.gel_modulus_pa = v; }},
      {"sensor.gel_poisson", [](C& c, double v) { c.sensor.gel_poisson = v; }},
      {"sensor.dome_sag_mm", [](C& c, double v) { c.sensor.dome_sag_mm = v; }},
      {"sensor.lights[0].azimuth_deg", [](C& c, double v) { c.sensor.lights[0].azimuth_deg = v; }},
      {"sensor.lights[2].rgb[1]", [](C& c, double v) { c.sensor.lights[2].rgb[1] = v; }},
      {"sensor.light_elevation", [](C& c, double v) { c.sensor.light_elevation = v; }},
      {"sensor.background_rgb[2]", [](C& c, double v) { c.sensor.background_rgb[2] = v; }},
      {"sensor.background_nonuniformity_dn",
       [](C& c, double v) { c.sensor.background_nonuniformity_dn = v; }},
      {"sensor.vignetting", [](C& c, double v) { c.sensor.vignetting = v; }},
      {"sensor.marker_pitch_mm", [](C& c, double v) { c.sensor.marker_pitch_mm = v; }},
      {"sensor.marker_radius_mm", [](C& c, double v) { c.sensor.marker_radius_mm = v; }},
      {"sensor.noise_sigma_dn", [](C& c, double v) { c.sensor.noise_sigma_dn = v; }},
      {"sensor.channel_gain[0]", [](C& c, double v) { c.sensor.channel_gain[0] = v; }},
      {"scene.geometry.radius_mm", [](C& c, double v) { c.scene.geometry.radius_mm = v; }},
      {"scene.geometry.length_mm", [](C& c, double v) { c.scene.geometry.length_mm = v; }},
      {"scene.geometry.angle_deg", [](C& c, double v) { c.scene.geometry.angle_deg = v; }},
      {"scene.geometry.center_x_mm", [](C& c, double v) { c.scene.geometry.center_x_mm = v; }},
      {"scene.geometry.center_y_mm", [](C& c, double v) { c.scene.geometry.center_y_mm = v; }},
      {"scene.geometry.height_map_mm[1234]",
       [](C& c, double v) {
         c.scene.geometry.shape = Shape::kHeightMap;
         c.scene.geometry.height_map_mm.assign(
             static_cast<size_t>(c.sensor.height) * static_cast<size_t>(c.sensor.width), 0.0f);
         c.scene.geometry.height_map_mm[1234] = static_cast<float>(v);
       }},
      {"scene.texture.sq_um", [](C& c, double v) { c.scene.texture.sq_um = v; }},
      {"scene.texture.correlation_length_mm",
       [](C& c, double v) { c.scene.texture.correlation_length_mm = v; }},
      {"scene.texture.hurst", [](C& c, double v) { c.scene.texture.hurst = v; }},
      {"scene.mechanics.modulus_pa", [](C& c, double v) { c.scene.mechanics.modulus_pa = v; }},
      {"scene.mechanics.poisson", [](C& c, double v) { c.scene.mechanics.poisson = v; }},
      {"scene.mechanics.local_radius_mm",
       [](C& c, double v) { c.scene.mechanics.local_radius_mm = v; }},
      {"scene.mechanics.layer_mm", [](C& c, double v) { c.scene.mechanics.layer_mm = v; }},
      {"scene.loading.force_n", [](C& c, double v) { c.scene.loading.force_n = v; }},
      {"scene.loading.press_mm", [](C& c, double v) { c.scene.loading.press_mm = v; }},
      {"scene.loading.shear_x_n", [](C& c, double v) { c.scene.loading.shear_x_n = v; }},
      {"scene.loading.shear_y_n", [](C& c, double v) { c.scene.loading.shear_y_n = v; }},
      {"scene.loading.torque_nmm", [](C& c, double v) { c.scene.loading.torque_nmm = v; }},
      {"scene.loading.friction", [](C& c, double v) { c.scene.loading.friction = v; }},
      {"scene.loading.slip_mm", [](C& c, double v) { c.scene.loading.slip_mm = v; }},
      {"options.led_gain", [](C& c, double v) { c.options.led_gain = v; }},
      {"options.noise_sigma_dn", [](C& c, double v) { c.options.noise_sigma_dn = v; }},
  };
}

std::vector<InvalidCase> build() {
  InvalidCase base;
  auto mini = sensor_profile("gelsight-mini");
  if (mini.ok()) base.sensor = mini.value();
  std::vector<InvalidCase> v;
  const struct {
    const char* tag;
    double value;
  } bad[] = {{"nan", std::numeric_limits<double>::quiet_NaN()},
             {"+inf", std::numeric_limits<double>::infinity()},
             {"-inf", -std::numeric_limits<double>::infinity()}};
  for (const Field& f : fields()) {
    for (const auto& b : bad) {
      InvalidCase c = base;
      c.name = std::string(b.tag) + ":" + std::string(f.name);
      c.field = f.name;
      f.set(c, b.value);
      v.push_back(std::move(c));
    }
  }
  // A few finite values out of range.
  auto range = [&](std::string name, std::string_view field, auto set) {
    InvalidCase c = base;
    c.name = std::move(name);
    c.field = field;
    set(c);
    v.push_back(std::move(c));
  };
  range("range:negative-object-modulus", "scene.mechanics.modulus_pa",
        [](InvalidCase& c) { c.scene.mechanics.modulus_pa = -1; });
  range("range:force-over-1000", "scene.loading.force_n",
        [](InvalidCase& c) { c.scene.loading.force_n = 1001; });
  range("range:no-load-mode", "scene.loading.force_n", [](InvalidCase& c) {
    c.scene.loading.force_n = -1;
    c.scene.loading.press_mm = -1;
  });
  range("range:jpeg-quality-101", "options.jpeg_quality",
        [](InvalidCase& c) { c.options.jpeg_quality = 101; });
  range("range:jpeg-passes-0", "options.jpeg_passes",
        [](InvalidCase& c) { c.options.jpeg_passes = 0; });
  range("range:light-count-5", "sensor.light_count",
        [](InvalidCase& c) { c.sensor.light_count = 5; });
  range("range:raw-format", "sensor.raw_format",
        [](InvalidCase& c) { c.sensor.raw_format = "png"; });
  range("range:raw-crop-0.5", "sensor.raw_crop", [](InvalidCase& c) { c.sensor.raw_crop = 0.5; });
  range("range:shape", "scene.geometry.shape",
        [](InvalidCase& c) { c.scene.geometry.shape = static_cast<Shape>(42); });
  range("range:gel-poisson-0.5", "sensor.gel_poisson",
        [](InvalidCase& c) { c.sensor.gel_poisson = 0.5; });
  return v;
}

}  // namespace

std::span<const InvalidCase> invalid_parameter_cases() {
  static const std::vector<InvalidCase> cases = build();
  return cases;
}

}  // namespace tlvlink::sim
