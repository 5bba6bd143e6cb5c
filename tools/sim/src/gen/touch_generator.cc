// Touch sessions: one object (a material sample of a random class) per session, pressed
// several times with varied force, position, contact shape and a little shear. Every frame is
// rendered, paired with a vision image of the object and described.

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "gen/rng.h"
#include "gen/sensor_instances.h"
#include "gen/session_names.h"
#include "tlvlink/sim/describe.h"
#include "tlvlink/sim/generate.h"
#include "tlvlink/sim/vision.h"

namespace tlvlink::sim {
namespace {

using internal::derive_seed;
using internal::Rng;
using internal::Stream;
using internal::tag;

constexpr int32_t kMaxSessions = 10'000'000;  // session start times stay within 4-digit years
constexpr int32_t kMaxFramesPerSession = 100'000;
// Presses (README "Touch sessions").
// Ranges favour imprints the renderer shows clearly: at 2 N a 20 mm sphere changes the image
// by ~10 DN, a 40 mm one by ~7 DN (noise sigma 3 DN); TAG's presses are firm hand presses.
constexpr double kMinForceN = 1.0, kMaxForceN = 15.0;      // log-uniform
constexpr double kSphereMinMm = 2.0, kSphereMaxMm = 25.0;  // log-uniform radii
constexpr double kCylinderMinMm = 2.0, kCylinderMaxMm = 20.0;
constexpr double kMaxOffsetMm = 3.0;        // contact position jitter
constexpr double kMaxShearFraction = 0.3;   // |Q| <= 0.3 mu F: stick, some lag
constexpr double kMaxTorqueFraction = 0.1;  // |M_z| <= 0.1 mu F * 1 mm
constexpr double kFlatLocalRadiusMm = 20.0, kEdgeLocalRadiusMm = 10.0;
constexpr double kBroadFaceMinMm = 25.0, kBroadFaceMaxMm = 80.0;  // "flat" smooth faces

struct Press {
  Shape shape = Shape::kSphere;
  double force_n = 1;
};

Status validate(const TouchSetOptions& o) {
  TLV_ENSURE(o.sessions >= 1 && o.sessions <= kMaxSessions, ErrorCode::kInvalidArgument,
             "touch set: sessions = %d is outside 1..%d", o.sessions, kMaxSessions);
  TLV_ENSURE(o.frames_per_session >= 1 && o.frames_per_session <= kMaxFramesPerSession,
             ErrorCode::kInvalidArgument, "touch set: frames_per_session = %d is outside 1..%d",
             o.frames_per_session, kMaxFramesPerSession);
  TLV_ENSURE(o.vision_height >= 1 && o.vision_height <= kMaxVisionSide && o.vision_width >= 1 &&
                 o.vision_width <= kMaxVisionSide,
             ErrorCode::kInvalidArgument, "touch set: vision size %dx%d is outside 1..%d",
             o.vision_height, o.vision_width, kMaxVisionSide);
  TLV_ENSURE(o.markers_fraction >= 0 && o.markers_fraction <= 1, ErrorCode::kInvalidArgument,
             "touch set: markers_fraction = %g is outside [0, 1]", o.markers_fraction);
  TLV_ENSURE(o.sensor_instances >= 1 && o.sensor_instances <= kMaxSensorInstances,
             ErrorCode::kInvalidArgument, "touch set: sensor_instances = %d is outside 1..%d",
             o.sensor_instances, kMaxSensorInstances);
  return {};
}

class TouchGenerator final : public TouchSampleGenerator {
 public:
  TouchGenerator(const TouchSetOptions& o, std::vector<std::unique_ptr<internal::RendererCache>> r,
                 std::shared_ptr<const Describer> d)
      : options_(o), renderers_(std::move(r)), describer_(std::move(d)) {
    options_.sensor = {};  // the caller's string may not outlive us; profiles are in renderers_
  }

  int64_t size() const override {
    return static_cast<int64_t>(options_.sessions) * options_.frames_per_session;
  }

  Status generate(int64_t index, TouchSample& out) override {
    TLV_ENSURE(index >= 0 && index < size(), ErrorCode::kInvalidArgument,
               "touch set: sample %lld is outside 0..%lld", static_cast<long long>(index),
               static_cast<long long>(size() - 1));
    const uint64_t seed = options_.seed;
    const int64_t session = index / options_.frames_per_session;
    // The object: same for every frame of the session.
    Rng object_rng(derive_seed(seed, {tag(Stream::kSession), static_cast<uint64_t>(session)}));
    const int32_t cls = object_rng.int_in(0, kMaterialClassCount - 1);
    TLV_ASSIGN_OR_RETURN(out.material, sample_material(cls, object_rng.next()));
    const uint64_t appearance = object_rng.next(), texture_seed = object_rng.next();
    out.session = internal::session_name(seed, session);
    out.frame_index = static_cast<int32_t>(index % options_.frames_per_session);
    out.object_id = static_cast<int32_t>(session);
    // The session's sensor: consecutive frames of a session reuse the kept Renderer. A mixed
    // set draws the profile per session too (a single profile draws nothing: same bytes).
    const size_t profile = internal::item_profile(seed, session, renderers_.size());
    internal::RendererCache& cache = *renderers_[profile];
    out.sensor = cache.profile().name;
    out.sensor_instance =
        internal::touch_session_instance(seed, session, options_.sensor_instances);
    TLV_ASSIGN_OR_RETURN(Renderer * renderer, cache.get(out.sensor_instance));

    // The press.
    Rng rng(derive_seed(seed, {tag(Stream::kFrame), static_cast<uint64_t>(index)}));
    ContactScene scene;
    const Press press = make_press(out.material, texture_seed, rng, scene);
    RenderOptions render;
    render.markers =
        options_.markers || internal::item_has_markers(seed, session, options_.markers_fraction);
    TLV_TRY(renderer->render(
        scene, render, derive_seed(seed, {tag(Stream::kRender), static_cast<uint64_t>(index)}),
        frame_));
    internal::copy_frame(frame_, out.touch);
    out.contact = frame_.state;

    const uint64_t view_seed =
        derive_seed(seed, {tag(Stream::kVision), static_cast<uint64_t>(index)});
    TLV_TRY(render_vision_image(out.material, appearance, random_vision_view(view_seed), view_seed,
                                options_.vision_height, options_.vision_width, out.vision));

    describer_->describe(
        tactile_traits(out.material, press.force_n, press.shape),
        derive_seed(seed, {tag(Stream::kDescription), static_cast<uint64_t>(index)}), description_);
    out.sentence_desc = description_.sentence;
    out.phrases = description_.phrases;
    return {};
  }

 private:
  // Shape by the class's plausibility, force log-uniform, offset, a little shear and twist.
  static Press make_press(const MaterialSample& m, uint64_t texture_seed, Rng& rng,
                          ContactScene& s) {
    const MaterialClass& cls = *material_class(m.class_id).value();
    Press p;
    const auto shape = static_cast<PressShape>(rng.weighted(cls.press_shapes));
    ObjectGeometry& g = s.geometry;
    g.center_x_mm = rng.uniform(-kMaxOffsetMm, kMaxOffsetMm);
    g.center_y_mm = rng.uniform(-kMaxOffsetMm, kMaxOffsetMm);
    g.angle_deg = rng.uniform(0, 180);
    double radius = 0;  // local radius L_o before the compliant-layer cap
    switch (shape) {
      case PressShape::kSphere:
        g.shape = Shape::kSphere;
        g.radius_mm = radius = rng.log_uniform(kSphereMinMm, kSphereMaxMm);
        break;
      case PressShape::kCylinder:
        g.shape = Shape::kCylinder;
        g.radius_mm = radius = rng.log_uniform(kCylinderMinMm, kCylinderMaxMm);
        g.length_mm = rng.uniform(20, 100);
        break;
      case PressShape::kFlat:
        if (m.rough == 1) {  // the whole gel on the surface: its texture is the image
          g.shape = Shape::kFlatPlate;
          radius = kFlatLocalRadiusMm;
        } else {  // a smooth face shows nothing under uniform pressure: a broad, slightly curved
                  // face
          g.shape = Shape::kSphere;
          g.radius_mm = radius = rng.log_uniform(kBroadFaceMinMm, kBroadFaceMaxMm);
        }
        break;
      case PressShape::kEdge:
        g.shape = Shape::kBoxEdge;
        radius = kEdgeLocalRadiusMm;
        break;
    }
    s.mechanics.local_radius_mm = compliant_length_mm(m, radius);
    s.mechanics.layer_mm = m.layer_mm;
    p.shape = shape == PressShape::kFlat ? Shape::kFlatPlate : g.shape;  // described as flat
    p.force_n = rng.log_uniform(kMinForceN, kMaxForceN);
    s.texture.sq_um = m.sq_um;
    s.texture.correlation_length_mm = m.correlation_length_mm;
    s.texture.hurst = m.hurst;
    s.texture.seed = texture_seed;
    s.mechanics.modulus_pa = m.modulus_pa;
    s.mechanics.poisson = m.poisson;
    Loading& l = s.loading;
    l.force_n = p.force_n;
    l.friction = m.friction;
    const double q = rng.uniform(0, kMaxShearFraction) * m.friction * p.force_n;
    const double dir = rng.uniform(0, 2 * std::numbers::pi);
    l.shear_x_n = q * std::cos(dir);
    l.shear_y_n = q * std::sin(dir);
    l.torque_nmm = rng.uniform(-kMaxTorqueFraction, kMaxTorqueFraction) * m.friction * p.force_n;
    return p;
  }

  TouchSetOptions options_;
  std::vector<std::unique_ptr<internal::RendererCache>> renderers_;  // one per profile
  std::shared_ptr<const Describer> describer_;
  Frame frame_;
  Description description_;
};

}  // namespace

Result<std::unique_ptr<TouchSampleGenerator>> TouchSampleGenerator::create(
    const TouchSetOptions& options) {
  TLV_TRY(validate(options));
  // The set's sensor instances of each profile; their backgrounds are fixed by the dataset seed.
  std::vector<std::unique_ptr<internal::RendererCache>> renderers;
  for (const std::string& name : internal::profile_names(options.sensor)) {
    TLV_ASSIGN_OR_RETURN(const SensorProfile profile, sensor_profile(name));
    TLV_ASSIGN_OR_RETURN(
        std::unique_ptr<internal::RendererCache> cache,
        internal::RendererCache::create(profile, options.seed, options.sensor_instances));
    renderers.push_back(std::move(cache));
  }
  TLV_ASSIGN_OR_RETURN(std::shared_ptr<const Describer> describer, Describer::create());
  return std::unique_ptr<TouchSampleGenerator>(
      new TouchGenerator(options, std::move(renderers), std::move(describer)));
}

}  // namespace tlvlink::sim
