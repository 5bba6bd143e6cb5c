// Feel-style grasp episodes: two fingers x before / during / after. Variables and label come
// from the grasp prior and the friction-limit rule (grasp_model.h); the frames show them:
//   before  no contact (background, markers, noise);
//   during  fingers closed on the object, still supported: normal load P, little shear;
//   after   the lift: held -> stick / partial slip under Q and M_z; dropped with rho < 3 ->
//           gross slip (imprint travels 0.5-5 mm); rho >= 3 or a missing finger -> contact lost.
// The after loads are rescaled by the rendered contact (force, radius) so the renderer's slip
// ratio equals the label's rho for that finger: the frames never contradict the label.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "gen/grasp_model.h"
#include "gen/grasp_profile.h"
#include "gen/sensor_instances.h"
#include "gen/session_names.h"
#include "tlvlink/sim/generate.h"
#include "tlvlink/sim/live_path.h"
#include "tlvlink/sim/vision.h"

namespace tlvlink::sim {
namespace {

using internal::derive_seed;
using internal::Rng;
using internal::Stream;
using internal::tag;

constexpr int32_t kMaxObjects = 10'000'000;
constexpr int32_t kMaxGraspsPerObject = 100'000;
constexpr double kDuringShearMaxN = 0.2;  // object resting on the table: hardly any shear
constexpr double kDropRatio = 3.0;        // rho beyond this: the object is gone after the lift
constexpr double kSlipMinMm = 0.5, kSlipMaxMm = 5.0;
constexpr double kHeldRatioMax = 0.999;  // rendered rho of a held finger stays below 1
constexpr double kLiftShift = 0.2;       // vision: a held object moves up in the image

Status validate(const GraspSetOptions& o) {
  TLV_ENSURE(o.objects >= 1 && o.objects <= kMaxObjects, ErrorCode::kInvalidArgument,
             "grasp set: objects = %d is outside 1..%d", o.objects, kMaxObjects);
  TLV_ENSURE(o.grasps_per_object >= 1 && o.grasps_per_object <= kMaxGraspsPerObject,
             ErrorCode::kInvalidArgument, "grasp set: grasps_per_object = %d is outside 1..%d",
             o.grasps_per_object, kMaxGraspsPerObject);
  TLV_ENSURE(o.vision_height >= 1 && o.vision_height <= kMaxVisionSide && o.vision_width >= 1 &&
                 o.vision_width <= kMaxVisionSide,
             ErrorCode::kInvalidArgument, "grasp set: vision size %dx%d is outside 1..%d",
             o.vision_height, o.vision_width, kMaxVisionSide);
  TLV_ENSURE(o.sensor_instances >= 1 && o.sensor_instances <= kMaxSensorInstances,
             ErrorCode::kInvalidArgument, "grasp set: sensor_instances = %d is outside 1..%d",
             o.sensor_instances, kMaxSensorInstances);
  TLV_ENSURE(o.markers_fraction >= 0 && o.markers_fraction <= 1, ErrorCode::kInvalidArgument,
             "grasp set: markers_fraction = %g is outside [0, 1]", o.markers_fraction);
  TLV_ENSURE(o.live_path_fraction >= 0 && o.live_path_fraction <= 1, ErrorCode::kInvalidArgument,
             "grasp set: live_path_fraction = %g is outside [0, 1]", o.live_path_fraction);
  TLV_ENSURE(!(o.live_path && o.live_path_fraction > 0), ErrorCode::kInvalidArgument,
             "grasp set: live_path (every frame) and live_path_fraction = %g exclude each other",
             o.live_path_fraction);
  return {};
}

// Translation and torsion parts of finger f's slip ratio under the label's physics.
struct FingerRatio {
  double translation = 0, torsion = 0;
};
FingerRatio finger_ratio(const GraspVariables& v, int32_t f) {
  const double limit = v.friction * v.grip_force_n;
  const double a = std::sqrt(std::max(v.contact_area_mm2[f], 0.0) / std::numbers::pi);
  const double q = v.mass_kg * (kGravity + v.lift_accel_mps2) / 2;
  const double m = v.mass_kg * kGravity * v.com_offset_mm / 2;
  const double torsion = 3 * std::numbers::pi / 16 * limit * a;
  FingerRatio r;
  r.translation = limit > 0 ? std::min(q / limit, kMaxSlipRatio) : (q > 0 ? kMaxSlipRatio : 0.0);
  r.torsion = torsion > 0 ? std::min(m / torsion, kMaxSlipRatio) : (m > 0 ? kMaxSlipRatio : 0.0);
  return r;
}

// One sensor profile of the set: its sensor instances and the gel the grasp physics uses.
struct ProfileSensors {
  std::unique_ptr<internal::RendererCache> renderers;
  internal::GelContactModel gel;
  std::unique_ptr<LivePath> live;  // GraspSetOptions::live_path: the sensor's raw camera + decoder
};

class GraspGenerator final : public GraspEpisodeGenerator {
 public:
  GraspGenerator(const GraspSetOptions& o, std::vector<ProfileSensors> profiles)
      : options_(o), profiles_(std::move(profiles)) {
    options_.sensor = {};  // the caller's string may not outlive us; profiles are in profiles_
  }

  int64_t size() const override {
    return static_cast<int64_t>(options_.objects) * options_.grasps_per_object;
  }

  Status generate(int64_t index, GraspEpisode& out) override {
    return generate_impl(index, out, nullptr);
  }
  Status generate(int64_t index, GraspEpisode& out, GraspScenes& scenes) override {
    return generate_impl(index, out, &scenes);
  }

 private:
  Status generate_impl(int64_t index, GraspEpisode& out, GraspScenes* scenes) {
    TLV_ENSURE(index >= 0 && index < size(), ErrorCode::kInvalidArgument,
               "grasp set: episode %lld is outside 0..%lld", static_cast<long long>(index),
               static_cast<long long>(size() - 1));
    const uint64_t seed = options_.seed;
    const int64_t object_index = index / options_.grasps_per_object;
    const internal::GraspObject object = internal::sample_grasp_object(seed, object_index);
    const internal::GraspSetup setup = internal::sample_grasp_setup(seed, index);
    // The object's sensor type: a gripper carries one, so both fingers and every grasp of the
    // object share it (a single-profile set draws nothing: same bytes).
    ProfileSensors& sensors =
        profiles_[internal::item_profile(seed, object_index, profiles_.size())];
    out.sensor = sensors.renderers->profile().name;
    out.variables = internal::grasp_variables(object, setup, sensors.gel);
    out.is_gripping = grasp_succeeds(out.variables);
    out.object_name = internal::object_name(object.material.class_id, object_index);
    out.object_id = static_cast<int32_t>(object_index);
    out.material = object.material;
    for (int32_t f = 0; f < kFingers; ++f)
      out.sensor_instance[f] =
          internal::grasp_finger_instance(seed, index, f, options_.sensor_instances);

    Rng rng(derive_seed(seed, {tag(Stream::kGrasp), static_cast<uint64_t>(index), 1}));
    const bool both = setup.finger_in_contact[0] && setup.finger_in_contact[1];
    const bool dropped = !both || out.variables.slip_ratio >= kDropRatio;
    const double slip_mm = rng.uniform(kSlipMinMm, kSlipMaxMm);
    RenderOptions render;
    render.markers = options_.markers ||
                     internal::item_has_markers(seed, object_index, options_.markers_fraction);
    out.live_path = options_.live_path ||
                    internal::item_takes_live_path(seed, object_index, options_.live_path_fraction);
    for (int32_t f = 0; f < kFingers; ++f) {
      // Finger f's sensor; the cache keeps both fingers' Renderers.
      TLV_ASSIGN_OR_RETURN(Renderer * renderer, sensors.renderers->get(out.sensor_instance[f]));
      ContactScene scene = base_scene(object, setup, f);
      auto noise = [&](Moment m) {
        return derive_seed(seed, {tag(Stream::kRender), static_cast<uint64_t>(index),
                                  static_cast<uint64_t>(f), static_cast<uint64_t>(m)});
      };
      // before: the fingers are open.
      ContactScene open = scene;
      open.geometry.shape = Shape::kNone;
      // Every tactile frame of the episode through the same live path (or none).
      LivePath* live = out.live_path ? sensors.live.get() : nullptr;
      TLV_TRY(render_into(*renderer, live, open, render, noise(Moment::kBefore), out, f,
                          Moment::kBefore));
      // during: closed on the resting object (a missing finger closes on air).
      ContactScene during = setup.finger_in_contact[f] ? scene : open;
      const double dir = rng.uniform(0, 2 * std::numbers::pi), q = rng.uniform(0, kDuringShearMaxN);
      during.loading.shear_x_n = q * std::cos(dir);
      during.loading.shear_y_n = q * std::sin(dir);
      TLV_TRY(render_into(*renderer, live, during, render, noise(Moment::kDuring), out, f,
                          Moment::kDuring));
      // after: the lift.
      ContactScene after = dropped ? open : scene;
      if (!dropped) {
        set_lift_load(out.variables, f, out.states[f][static_cast<int>(Moment::kDuring)],
                      out.is_gripping, slip_mm, after.loading);
      }
      TLV_TRY(render_into(*renderer, live, after, render, noise(Moment::kAfter), out, f,
                          Moment::kAfter));
      if (scenes != nullptr) {
        scenes->open[f] = open;
        scenes->during[f] = during;
        scenes->after[f] = after;
        scenes->render = render;
        scenes->sensor_seed[f] = sensor_instance_seed(seed, out.sensor_instance[f]);
      }
    }
    return render_vision(object, index, out);
  }

  ContactScene base_scene(const internal::GraspObject& object, const internal::GraspSetup& setup,
                          int32_t f) const {
    ContactScene s;
    s.geometry = internal::finger_geometry(object, setup, f);
    s.texture.sq_um = object.material.sq_um;
    s.texture.correlation_length_mm = object.material.correlation_length_mm;
    s.texture.hurst = object.material.hurst;
    s.texture.seed = object.texture_seed + static_cast<uint64_t>(f);  // the two sides differ
    s.mechanics = object.mechanics;
    s.loading.force_n = setup.grip_force_n;
    s.loading.friction = object.material.friction;
    return s;
  }

  // Q along +y (gravity in the gel plane), M_z of opposite sign on the two fingers, both scaled
  // so the renderer's rho (from the during contact) is the label's: the finger's own rho when
  // held (kept < 1), the grasp's rho (>= 1) when it slips.
  static void set_lift_load(const GraspVariables& v, int32_t f, const ContactState& during,
                            bool held, double slip_mm, Loading& l) {
    const FingerRatio r = finger_ratio(v, f);
    const double rho = std::hypot(r.translation, r.torsion);
    const double target = held ? std::min(rho, kHeldRatioMax) : std::max(v.slip_ratio, 1.0);
    const double scale = rho > 0 ? target / rho : 0.0;
    const double limit = v.friction * during.force_n;
    l.shear_x_n = 0;
    l.shear_y_n = r.translation * scale * limit;
    l.torque_nmm = (f == 0 ? 1 : -1) * r.torsion * scale * 3 * std::numbers::pi / 16 * limit *
                   during.contact_radius_mm;
    l.slip_mm = held ? 0.0 : slip_mm;
  }

  Status render_into(Renderer& renderer, LivePath* live, const ContactScene& scene,
                     const RenderOptions& render, uint64_t noise, GraspEpisode& out, int32_t f,
                     Moment m) {
    TLV_TRY(renderer.render(scene, render, noise, frame_));
    if (live != nullptr) TLV_TRY(live->apply(frame_.rgb));
    internal::copy_frame(frame_, out.frames[f][static_cast<int>(m)]);
    out.states[f][static_cast<int>(m)] = frame_.state;
    return {};
  }

  // kinectA stand-in: the object from a fixed camera; after the lift a held object has moved up,
  // a dropped one has tipped over.
  Status render_vision(const internal::GraspObject& object, int64_t index, GraspEpisode& out) {
    const uint64_t seed = options_.seed;
    const uint64_t view_seed =
        derive_seed(seed, {tag(Stream::kVision), static_cast<uint64_t>(index)});
    VisionView view = random_vision_view(view_seed);
    for (int m = 0; m < kMoments; ++m) {
      VisionView v = view;
      if (m == static_cast<int>(Moment::kAfter)) {
        if (out.is_gripping)
          v.shift_y += kLiftShift;
        else
          v.rotation_deg += 25;
      }
      TLV_TRY(render_vision_image(object.material, object.texture_seed, v,
                                  derive_seed(view_seed, {static_cast<uint64_t>(m)}),
                                  options_.vision_height, options_.vision_width, out.vision[m]));
    }
    return {};
  }

  GraspSetOptions options_;
  std::vector<ProfileSensors> profiles_;  // one per profile of options.sensor, in order
  Frame frame_;
};

}  // namespace

Result<std::unique_ptr<GraspEpisodeGenerator>> GraspEpisodeGenerator::create(
    const GraspSetOptions& options) {
  TLV_TRY(validate(options));
  std::vector<ProfileSensors> profiles;
  for (const std::string& name : internal::profile_names(options.sensor)) {
    TLV_ASSIGN_OR_RETURN(const SensorProfile profile, sensor_profile(name));
    ProfileSensors p;
    p.gel = internal::gel_contact_model(profile);
    TLV_ASSIGN_OR_RETURN(p.renderers, internal::RendererCache::create(profile, options.seed,
                                                                      options.sensor_instances));
    if (options.live_path || options.live_path_fraction > 0) {
      TLV_ASSIGN_OR_RETURN(p.live, LivePath::create(profile));
    }
    profiles.push_back(std::move(p));
  }
  return std::unique_ptr<GraspEpisodeGenerator>(new GraspGenerator(options, std::move(profiles)));
}

}  // namespace tlvlink::sim
