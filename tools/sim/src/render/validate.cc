// Parameter validation of sensor profiles, scenes and render options. Ranges are the documented
// ones (headers and tools/sim/REFERENCE.md); errors name the field, e.g. "scene.loading.force_n".
#include <cstdio>

#include "render/check.h"
#include "tlvlink/sim/renderer.h"

namespace tlvlink::sim {

using internal::check_finite;
using internal::check_int_range;
using internal::check_range;

namespace {

// "prefix[i].suffix" field names for array elements, in a stack buffer (no allocation).
struct FieldName {
  char text[64];
  FieldName(const char* prefix, int i, const char* suffix) {
    std::snprintf(text, sizeof(text), "%s[%d]%s", prefix, i, suffix);
  }
};

Status check_rgb(const char* prefix, const std::array<double, 3>& v, double lo, double hi) {
  for (int c = 0; c < 3; ++c) TLV_TRY(check_range(FieldName(prefix, c, "").text, v[c], lo, hi));
  return {};
}

}  // namespace

Status validate(const SensorProfile& p) {
  TLV_ENSURE(!p.name.empty(), ErrorCode::kInvalidArgument, "sensor.name is empty");
  TLV_TRY(check_int_range("sensor.height", p.height, 16, 4096));
  TLV_TRY(check_int_range("sensor.width", p.width, 16, 4096));
  TLV_TRY(check_range("sensor.mm_per_px", p.mm_per_px, 0.01, 0.5));
  TLV_ENSURE((p.raw_height == 0) == (p.raw_width == 0), ErrorCode::kInvalidArgument,
             "sensor.raw_height = %d and sensor.raw_width = %d: set both or neither", p.raw_height,
             p.raw_width);
  if (p.raw_height != 0) {
    TLV_TRY(check_int_range("sensor.raw_height", p.raw_height, 16, 16384));
    TLV_TRY(check_int_range("sensor.raw_width", p.raw_width, 16, 16384));
  }
  TLV_TRY(check_range("sensor.raw_crop", p.raw_crop, 0, 0.45));
  TLV_ENSURE(p.raw_format == "rgb" || p.raw_format == "mjpeg" || p.raw_format == "yuyv",
             ErrorCode::kInvalidArgument,
             "sensor.raw_format = \"%.*s\" (expected \"rgb\", \"mjpeg\" or \"yuyv\")",
             static_cast<int>(p.raw_format.size()), p.raw_format.data());
  TLV_TRY(check_range("sensor.gel_thickness_mm", p.gel_thickness_mm, 0.5, 10));
  TLV_TRY(check_range("sensor.gel_modulus_pa", p.gel_modulus_pa, 1e3, 1e8));
  TLV_TRY(check_range("sensor.gel_poisson", p.gel_poisson, 0, 0.499));
  TLV_TRY(check_range("sensor.dome_sag_mm", p.dome_sag_mm, 0, 2));
  TLV_TRY(check_int_range("sensor.light_count", p.light_count, 1, 4));
  for (int i = 0; i < p.light_count; ++i) {
    const Light& l = p.lights[static_cast<size_t>(i)];
    const FieldName az("sensor.lights", i, ".azimuth_deg");
    TLV_TRY(check_range(az.text, l.azimuth_deg, 0, 360));
    TLV_ENSURE(l.azimuth_deg < 360, ErrorCode::kInvalidArgument, "%s = %g must be < 360", az.text,
               l.azimuth_deg);
    const FieldName rgb("sensor.lights", i, ".rgb");
    TLV_TRY(check_rgb(rgb.text, l.rgb, 0, 2));
  }
  TLV_TRY(check_range("sensor.light_elevation", p.light_elevation, 0.05, 5));
  TLV_TRY(check_rgb("sensor.background_rgb", p.background_rgb, 0, 255));
  TLV_TRY(check_range("sensor.background_nonuniformity_dn", p.background_nonuniformity_dn, 0, 40));
  TLV_TRY(check_range("sensor.vignetting", p.vignetting, 0, 0.9));
  TLV_TRY(check_int_range("sensor.marker_rows", p.marker_rows, 1, 64));
  TLV_TRY(check_int_range("sensor.marker_cols", p.marker_cols, 1, 64));
  TLV_TRY(check_range("sensor.marker_pitch_mm", p.marker_pitch_mm, 0.3, 10));
  TLV_TRY(check_range("sensor.marker_radius_mm", p.marker_radius_mm, 0.05, 1));
  TLV_TRY(check_range("sensor.noise_sigma_dn", p.noise_sigma_dn, 0, 20));
  TLV_TRY(check_rgb("sensor.channel_gain", p.channel_gain, 0.5, 2));
  return {};
}

Status validate(const ContactScene& s) {
  const ObjectGeometry& g = s.geometry;
  TLV_ENSURE(g.shape <= Shape::kHeightMap, ErrorCode::kInvalidArgument,
             "scene.geometry.shape = %d is not a Shape", static_cast<int>(g.shape));
  TLV_TRY(check_range("scene.geometry.radius_mm", g.radius_mm, 0, 1e6));
  TLV_TRY(check_range("scene.geometry.length_mm", g.length_mm, 0, 1e6));
  TLV_TRY(check_range("scene.geometry.angle_deg", g.angle_deg, -360, 360));
  TLV_TRY(check_range("scene.geometry.center_x_mm", g.center_x_mm, -1e3, 1e3));
  TLV_TRY(check_range("scene.geometry.center_y_mm", g.center_y_mm, -1e3, 1e3));
  if (g.shape == Shape::kHeightMap) {
    TLV_ENSURE(!g.height_map_mm.empty(), ErrorCode::kInvalidArgument,
               "scene.geometry.height_map_mm is empty (shape is kHeightMap)");
    for (size_t i = 0; i < g.height_map_mm.size(); ++i) {
      const auto v = static_cast<double>(g.height_map_mm[i]);
      if (!(v >= -1e3 && v <= 1e3)) {  // also catches NaN
        return Error::make(ErrorCode::kInvalidArgument,
                           "scene.geometry.height_map_mm[%zu] = %g is not finite in [-1000, 1000]",
                           i, v);
      }
    }
  }
  const SurfaceTexture& t = s.texture;
  TLV_TRY(check_range("scene.texture.sq_um", t.sq_um, 0, 500));
  TLV_TRY(check_range("scene.texture.correlation_length_mm", t.correlation_length_mm, 0.01, 20));
  TLV_TRY(check_range("scene.texture.hurst", t.hurst, 0, 1));
  const ObjectMechanics& m = s.mechanics;
  TLV_TRY(check_range("scene.mechanics.modulus_pa", m.modulus_pa, 1e2, 1e13));
  TLV_TRY(check_range("scene.mechanics.poisson", m.poisson, 0, 0.5));
  TLV_TRY(check_range("scene.mechanics.local_radius_mm", m.local_radius_mm, 0.01, 1e6));
  TLV_TRY(check_range("scene.mechanics.layer_mm", m.layer_mm, 0, 1e6));
  const Loading& l = s.loading;
  TLV_TRY(check_finite("scene.loading.force_n", l.force_n));
  TLV_TRY(check_finite("scene.loading.press_mm", l.press_mm));
  if (l.force_n >= 0) {
    TLV_TRY(check_range("scene.loading.force_n", l.force_n, 0, 1000));
  } else {
    TLV_ENSURE(l.press_mm >= 0, ErrorCode::kInvalidArgument,
               "scene.loading.force_n = %g and scene.loading.press_mm = %g: set force_n >= 0 or "
               "press_mm >= 0",
               l.force_n, l.press_mm);
    TLV_TRY(check_range("scene.loading.press_mm", l.press_mm, 0, 20));
  }
  TLV_TRY(check_range("scene.loading.shear_x_n", l.shear_x_n, -1000, 1000));
  TLV_TRY(check_range("scene.loading.shear_y_n", l.shear_y_n, -1000, 1000));
  TLV_TRY(check_range("scene.loading.torque_nmm", l.torque_nmm, -1e5, 1e5));
  TLV_TRY(check_range("scene.loading.friction", l.friction, 0, 5));
  TLV_TRY(check_range("scene.loading.slip_mm", l.slip_mm, 0, 50));
  return {};
}

Status validate(const RenderOptions& o) {
  TLV_TRY(check_range("options.led_gain", o.led_gain, 0, 100));
  TLV_TRY(check_finite("options.noise_sigma_dn", o.noise_sigma_dn));
  if (o.noise_sigma_dn >= 0)
    TLV_TRY(check_range("options.noise_sigma_dn", o.noise_sigma_dn, 0, 50));
  if (o.jpeg_quality != 0) TLV_TRY(check_int_range("options.jpeg_quality", o.jpeg_quality, 1, 100));
  TLV_TRY(check_int_range("options.jpeg_passes", o.jpeg_passes, 1, 4));
  return {};
}

}  // namespace tlvlink::sim
