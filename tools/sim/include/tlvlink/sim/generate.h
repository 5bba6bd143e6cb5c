#pragma once
// Seeded, streaming generators of whole datasets: touch sessions (Touch100k / Touch-and-Go
// style: material, touch frame, vision image, descriptions) and Feel-style grasp episodes.
// Item i depends only on (seed, i), so generation can be split across threads and resumed, and
// the same options always give the same bytes.

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/sim/dataset.h"
#include "tlvlink/sim/materials.h"

namespace tlvlink::sim {

// Domain randomization over sensor instances. Every Renderer seed is one physical sensor (LED
// gains, background non-uniformity, white balance, exposure); a model trained on frames of one
// instance does not transfer to another, so a set can be drawn on several. Instance 0 is the
// one a set with a single instance uses (so `sensor_instances = 1` gives the bytes it always
// gave); instance k >= 1 is seeded by hashing (seed, k).
inline constexpr int32_t kMaxSensorInstances = 100'000;
// The vision images of touch and grasp sets: each side 1..kMaxVisionSide pixels.
inline constexpr int32_t kMaxVisionSide = 8192;
// The Renderer seed of instance `instance` (0 <= instance < kMaxSensorInstances) of a set with
// this seed: Renderer::create(profile, sensor_instance_seed(seed, k)) rebuilds that sensor.
uint64_t sensor_instance_seed(uint64_t seed, int32_t instance);

struct TouchSetOptions {
  int32_t sessions = 100;           // one object (one material sample) per session
  int32_t frames_per_session = 10;  // presses of that object at varied force/position/shear
  // A profile name, or several separated by commas ("gelsight-mini,digit"): then each session
  // is recorded on one of them, drawn by hashing (seed, session) (a mixed-profile set, for a
  // model that serves several sensor types; TouchSample::sensor says which). Frames keep their
  // profile's size. One profile gives the bytes it always gave.
  std::string_view sensor = "gelsight-mini";
  int32_t vision_height = 240, vision_width = 320;
  bool markers = false;
  // With markers false: the share of sessions recorded with a marker grid on the gel, [0, 1],
  // drawn per session by hashing (seed, session) (gels with and without markers, as real
  // sensors come; a model meant for both should see both). 0 = none, the bytes of before.
  double markers_fraction = 0;
  uint64_t seed = 1;
  // 1..kMaxSensorInstances simulated sensors; each session is recorded on one of them, drawn by
  // hashing (seed, session), like a real recording session on one physical sensor.
  int32_t sensor_instances = 1;
};

// Generators keep at most two sensor instances' Renderers alive (both fingers of an episode,
// or the current session plus one) and build another when a session or finger needs it: ~1 ms
// of sensor tables and ~12 MB of buffers on the GelSight Mini, so with sensor_instances > 1 a
// set costs ~1 ms more per session (touch, per generator thread) or per finger (grasp) and one
// more Renderer per generator; memory does not grow with sensor_instances.
class TouchSampleGenerator {
 public:
  static Result<std::unique_ptr<TouchSampleGenerator>> create(const TouchSetOptions& options);
  virtual ~TouchSampleGenerator() = default;
  virtual int64_t size() const = 0;  // sessions * frames_per_session
  // Fills `out` with sample `index` (0 <= index < size()), reusing its buffers.
  virtual Status generate(int64_t index, TouchSample& out) = 0;
};

struct GraspSetOptions {
  int32_t objects = 20;
  int32_t grasps_per_object = 10;
  // A profile name, or several separated by commas ("gelsight-mini,digit"): then each object's
  // grasps are recorded on one of them (both fingers alike, as a gripper carries one sensor
  // type), drawn by hashing (seed, object); GraspEpisode::sensor says which. An object's
  // episodes on a profile are the bytes a single-profile set of that seed gives.
  std::string_view sensor = "gelsight-mini";
  int32_t vision_height = 240, vision_width = 320;
  bool markers = true;  // shear shows in the marker field
  // With markers false: the share of objects whose grasps are recorded on gels with markers,
  // [0, 1], drawn per object by hashing (seed, object) (real grippers come with and without;
  // a grasp head meant for both should see both). 0 = none.
  double markers_fraction = 0;
  // Every tactile frame through its sensor's live image path (LivePath: the raw camera output
  // recovered by the board's decoder), as tlvlinkd sees it; states and labels are unchanged.
  bool live_path = false;
  // With live_path false: the share of objects whose frames go through the live path, [0, 1],
  // drawn per object by hashing (seed, object), independently of the markers (a head for the
  // board should learn from the frames the board sees as well as from the dataset's JPEG path;
  // GraspEpisode::live_path says which). 0 = none.
  double live_path_fraction = 0;
  uint64_t seed = 1;
  // 1..kMaxSensorInstances simulated sensors; fingers A and B are two physical sensors, so each
  // episode draws one instance per finger, independently, by hashing (seed, episode, finger).
  int32_t sensor_instances = 1;
};

// What one episode's frames are rendered from, per finger: a live scenario animates the grasp
// between these scenes (open gel -> closed on the resting object -> lifted) on each finger's own
// sensor (Renderer or RawCamera seeded with sensor_seed).
struct GraspScenes {
  ContactScene open[kFingers], during[kFingers], after[kFingers];
  RenderOptions render;
  uint64_t sensor_seed[kFingers] = {0, 0};
};

class GraspEpisodeGenerator {
 public:
  static Result<std::unique_ptr<GraspEpisodeGenerator>> create(const GraspSetOptions& options);
  virtual ~GraspEpisodeGenerator() = default;
  virtual int64_t size() const = 0;  // objects * grasps_per_object
  virtual Status generate(int64_t index, GraspEpisode& out) = 0;
  // The same episode and the scenes its frames were rendered from.
  virtual Status generate(int64_t index, GraspEpisode& out, GraspScenes& scenes) = 0;
};

// The friction-limit rule (gelsight-sim.md, GRASP EPISODE). Per finger, at the lift:
// tangential load Q = m (g + a_l) / 2, torque M_z = m g d / 2, contact radius a = sqrt(area/pi),
// rho = sqrt((Q / (mu P))^2 + (M_z / ((3 pi / 16) mu P a))^2); rho of the grasp = max over the
// fingers in contact, capped at kMaxSlipRatio so metadata stays finite.
inline constexpr double kGravity = 9.81;           // m/s^2
inline constexpr double kGraspSafetyFactor = 1.0;  // success needs rho <= 1 / SF
inline constexpr double kMaxSlipRatio = 1e6;
double grasp_slip_ratio(const GraspVariables& v);

// The success rule: both fingers in contact with P > 0, and either nothing to hold (m = 0) or
// rho <= 1 / SF. So mu = 0 with m > 0 fails, m = 0 succeeds when both fingers touch, and a
// missing finger always fails. Reads only the visible and hidden inputs of `v`, never its
// outcome fields.
bool grasp_succeeds(const GraspVariables& v);

// Accuracy of the Bayes-optimal predictor that sees only the visible variables (grip force,
// friction, contact areas, which fingers touch), estimated by Monte Carlo over the hidden ones
// with `samples` episodes; tells how hard the grasp task is. The episodes are fresh draws from
// the generator's prior (not the dataset's items). 0 when samples <= 0 or the sensor is unknown.
double grasp_oracle_accuracy(const GraspSetOptions& options, int64_t samples);

// The same estimate with the label balance it saw.
struct GraspOracleReport {
  int64_t samples = 0;
  double accuracy = 0;       // the oracle's accuracy on the fresh episodes
  double success_rate = 0;   // fraction of them with is_gripping
  double majority_rate = 0;  // accuracy of always predicting the majority label
  int64_t hidden_draws = 0;  // Monte Carlo draws of (mass, COM offset, lift accel) per episode
  // The same predictor when the friction is known only through the material class (what the
  // frames show of it: the class's texture, not mu itself): mu is marginalised uniformly over
  // the class's range, kOracleFrictionDraws values. Closer to what a model of the frames can
  // reach; the exact-mu figure above is the task's ceiling.
  double class_friction_accuracy = 0;
  // The same when the frames tell nothing of the material: mu marginalised over the grasp
  // prior's friction (every graspable class's range). What force, contact areas and finger
  // contact alone support; it ignores what the contact areas say of the material (its
  // stiffness), so a model may beat it slightly.
  double prior_friction_accuracy = 0;
};
Result<GraspOracleReport> grasp_oracle_report(const GraspSetOptions& options, int64_t samples);

// P(success | the visible variables of each episode) when the friction is known only as a
// distribution over material classes: class_weights[i][c] for class id c (each row summing to
// 1), mu within a class marginalised over its range as class_friction_accuracy does. What a
// predictor reaches that reads grip force and contact areas and recognises the material with
// that confidence. The hidden variables: the oracle's draws (kOracleHiddenDraws) from `seed`.
// Rows that are negative or do not sum to 1 (within 1e-6), or a length mismatch, are
// kInvalidArgument.
Result<std::vector<double>> grasp_success_given_class_weights(
    std::span<const GraspVariables> episodes,
    std::span<const std::array<double, kMaterialClassCount>> class_weights, uint64_t seed);

}  // namespace tlvlink::sim
