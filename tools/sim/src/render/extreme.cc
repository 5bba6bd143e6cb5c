// The named extreme set. Adding a case: append to build(); names are stable identifiers that
// other suites refer to, so never rename one.
#include "tlvlink/sim/extreme.h"

#include <vector>

namespace tlvlink::sim {
namespace {

SensorProfile profile(std::string_view name) {
  auto p = sensor_profile(name);
  return p.ok() ? p.value() : SensorProfile{};
}

ContactScene sphere(double force_n, double radius_mm = 5.0) {
  ContactScene s;
  s.geometry.shape = Shape::kSphere;
  s.geometry.radius_mm = radius_mm;
  s.loading.force_n = force_n;
  return s;
}

ContactScene shaped(Shape shape, double force_n) {
  ContactScene s = sphere(force_n);
  s.geometry.shape = shape;
  return s;
}

std::vector<ExtremeCase> build() {
  std::vector<ExtremeCase> v;
  const SensorProfile mini = profile("gelsight-mini");
  auto add = [&v](std::string_view name, std::string_view what, const SensorProfile& sensor,
                  const ContactScene& scene, const RenderOptions& options = {}) {
    v.push_back({name, what, sensor, scene, options});
  };
  RenderOptions markers;
  markers.markers = true;

  // Contact presence.
  add("no-contact", "no object: background + noise", mini, shaped(Shape::kNone, 5));
  add("zero-force", "object present, force 0: no contact", mini, sphere(0));
  ContactScene press0 = sphere(-1);
  press0.loading.press_mm = 0;
  add("press-0", "press depth 0: touching, no indentation", mini, press0);
  ContactScene outside = sphere(5);
  outside.geometry.center_x_mm = 1000;
  add("object-outside-view", "object centred 1 m away: no surface in view", mini, outside);

  // Lighting.
  RenderOptions saturated;
  saturated.led_gain = 10;
  add("saturated-leds", "LED gain x10: all-255 regions, no wrap", mini, sphere(5), saturated);
  RenderOptions blinding;
  blinding.led_gain = 100;
  add("leds-max", "LED gain 100 (range end) on a full-frame press", mini,
      shaped(Shape::kFlatPlate, 20), blinding);
  RenderOptions off;
  off.led_gain = 0;
  add("leds-off", "LEDs off: black frame (noise only)", mini, sphere(5), off);

  // Geometry.
  add("full-frame-contact", "flat plate: every pixel in contact, markers", mini,
      shaped(Shape::kFlatPlate, 20), markers);
  ContactScene deep_plate = shaped(Shape::kFlatPlate, -1);
  deep_plate.loading.press_mm = 20;
  add("full-frame-max-press", "flat plate pressed 20 mm (clamped at 0.9 t_g)", mini, deep_plate);
  ContactScene point = shaped(Shape::kPoint, 2);
  point.geometry.radius_mm = 0;
  add("point-contact", "sharp cone tip (radius 0): a -> 0, stiffness floors", mini, point, markers);
  add("tiny-sphere", "sphere of radius 0 (drawn as half a pixel)", mini, sphere(1, 0));
  add("huge-sphere", "sphere of radius 1e6 mm: locally flat", mini, sphere(5, 1e6));
  ContactScene edge = shaped(Shape::kBoxEdge, 5);
  edge.geometry.angle_deg = 30;
  add("step-edge", "sharp step edge: slope clamp", mini, edge);
  ContactScene cylinder = shaped(Shape::kCylinder, 8);
  cylinder.geometry.radius_mm = 2;
  cylinder.geometry.angle_deg = -45;
  add("cylinder", "capsule across the view", mini, cylinder);
  ContactScene spikes = shaped(Shape::kHeightMap, 5);
  spikes.geometry.height_map_mm.resize(static_cast<size_t>(mini.height * mini.width));
  for (int32_t y = 0; y < mini.height; ++y) {
    for (int32_t x = 0; x < mini.width; ++x) {  // +-1 mm checkerboard: every slope clamped
      spikes.geometry.height_map_mm[static_cast<size_t>(y * mini.width + x)] =
          ((x + y) % 2 == 0) ? 1.0f : -1.0f;
    }
  }
  add("height-map-spikes", "+-1 mm pixel checkerboard", mini, spikes);

  // Load.
  add("max-force", "1000 N on a sphere (depth limit)", mini, sphere(1000));
  ContactScene deep = sphere(-1);
  deep.loading.press_mm = 20;
  add("max-press", "sphere pressed 20 mm (clamped)", mini, deep);

  // Stiffness sweep of the object (kappa from ~0 to 1).
  const struct {
    std::string_view name;
    double modulus;
  } objects[] = {{"object-100pa", 1e2},   {"object-1kpa", 1e3},   {"object-100kpa", 1e5},
                 {"object-1mpa", 1e6},    {"object-100mpa", 1e8}, {"object-10gpa", 1e10},
                 {"object-1e12pa", 1e12}, {"object-1e13pa", 1e13}};
  for (const auto& o : objects) {
    ContactScene s = sphere(10);
    s.mechanics.modulus_pa = o.modulus;
    s.mechanics.poisson = 0.5;
    add(o.name, "object stiffness sweep: kappa in (0, 1], no division by zero", mini, s);
  }
  // Gel stiffness extremes.
  const struct {
    std::string_view name;
    double modulus;
  } gels[] = {{"gel-1kpa", 1e3}, {"gel-10kpa", 1e4}, {"gel-10mpa", 1e7}, {"gel-100mpa", 1e8}};
  for (const auto& g : gels) {
    SensorProfile s = mini;
    s.gel_modulus_pa = g.modulus;
    add(g.name, "gel modulus extreme", s, sphere(5));
  }
  SensorProfile thin = mini;
  thin.gel_thickness_mm = 0.5;
  add("gel-thin", "0.5 mm gel: narrow spreading, small depth limit", thin, sphere(20), markers);

  // Friction and slip.
  ContactScene mu0 = sphere(5);
  mu0.loading.friction = 0;
  mu0.loading.shear_x_n = 1;
  mu0.loading.slip_mm = 2;
  add("mu-0", "friction 0 with shear: immediate gross slip", mini, mu0, markers);
  ContactScene mu0_still = sphere(5);
  mu0_still.loading.friction = 0;
  add("mu-0-no-shear", "friction 0, no tangential load: rho = 0", mini, mu0_still, markers);
  ContactScene incipient = sphere(5);
  incipient.loading.shear_y_n = 0.95 * 0.6 * 5;
  add("incipient-slip", "Q = 0.95 mu P: small stick region", mini, incipient, markers);
  ContactScene wild = sphere(5);
  wild.loading.shear_x_n = 1000;
  wild.loading.shear_y_n = -1000;
  wild.loading.torque_nmm = 1e5;
  wild.loading.slip_mm = 50;
  add("max-shear-torque-slip", "range-end shear, torque and slip (imprint leaves the view)", mini,
      wild, markers);
  ContactScene point_twist = point;
  point_twist.loading.torque_nmm = 50;
  add("point-contact-torque", "torque on a point contact: torsional limit with a -> 0", mini,
      point_twist, markers);

  // Texture.
  ContactScene rough = shaped(Shape::kFlatPlate, 10);
  rough.texture = {500, 0.01, 0, 7};
  add("rough-max", "Sq 500 um, correlation 0.01 mm, Hurst 0", mini, rough);
  ContactScene wavy = sphere(5);
  wavy.texture = {500, 20, 1, 8};
  add("rough-long", "Sq 500 um at 20 mm correlation", mini, wavy);

  // Camera.
  RenderOptions q1;
  q1.jpeg_quality = 1;
  add("jpeg-q1", "JPEG quality 1", mini, sphere(5), q1);
  RenderOptions q100;
  q100.jpeg_quality = 100;
  add("jpeg-q100", "JPEG quality 100", mini, sphere(5), q100);
  RenderOptions feel;
  feel.jpeg_quality = 95;
  feel.jpeg_passes = 2;
  add("jpeg-q95-twice", "Feel-like double compression", mini, sphere(5), feel);
  RenderOptions noisy;
  noisy.noise_sigma_dn = 50;
  add("noise-max", "noise sigma 50 DN", mini, sphere(5), noisy);
  RenderOptions clean;
  clean.noise_sigma_dn = 0;
  add("noise-zero", "no noise", mini, sphere(5), clean);

  // Other sensors.
  add("digit-dome-plate", "DIGIT (domed gel, portrait) under a flat plate", profile("digit"),
      shaped(Shape::kFlatPlate, 5), markers);
  add("digit-640x480", "DIGIT 640x480 mode", profile("digit-640x480"), sphere(5), markers);
  add("r15-four-lights", "GelSight R1.5 with four lights", profile("gelsight-r1.5"), sphere(3),
      markers);
  return v;
}

}  // namespace

std::span<const ExtremeCase> extreme_cases() {
  static const std::vector<ExtremeCase> cases = build();
  return cases;
}

const ExtremeCase* find_extreme_case(std::string_view name) {
  for (const ExtremeCase& c : extreme_cases()) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

Status validate_all(const SensorProfile& sensor, const ContactScene& scene,
                    const RenderOptions& options) {
  TLV_TRY(validate(sensor));
  TLV_TRY(validate(scene));
  return validate(options);
}

}  // namespace tlvlink::sim
