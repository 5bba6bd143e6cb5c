#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "sensor_instances.h is internal to tools/sim: include its public headers instead"
#endif
// Domain randomization over sensor instances (generate.h): which instance draws a session or a
// finger, and the few Renderers a generator keeps for them. Internal.

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/sim/renderer.h"
#include "tlvlink/sim/sensor.h"

namespace tlvlink::sim::internal {

// The instance of touch session `session` in a set of `instances` (>= 1) sensors: hashed from
// (seed, session), so every frame of a session, on any thread, gets the same one.
int32_t touch_session_instance(uint64_t seed, int64_t session, int32_t instances);
// The instance of finger `finger` in grasp episode `episode`: hashed from (seed, episode,
// finger), independently for the two fingers (two physical sensors).
int32_t grasp_finger_instance(uint64_t seed, int64_t episode, int32_t finger, int32_t instances);

// The profile names of a set's sensor option: one name, or several separated by commas
// ("gelsight-mini,digit": a mixed-profile set), in order.
std::vector<std::string> profile_names(std::string_view sensor);
// Which of `profiles` (>= 1) records item `item` (a touch session, a grasp object): hashed from
// (seed, item); 0 without a draw when there is one profile (a single-profile set keeps its bytes).
size_t item_profile(uint64_t seed, int64_t item, size_t profiles);
// Whether item `item`'s gel has markers: a uniform draw from (seed, item) below `fraction`
// (false at 0 without a draw).
bool item_has_markers(uint64_t seed, int64_t item, double fraction);
// Whether an object's frames take the live path (GraspSetOptions::live_path_fraction).
bool item_takes_live_path(uint64_t seed, int64_t item, double fraction);

// The Renderers of a generator's sensor instances, at most kCapacity alive, least recently used
// evicted. Building one costs the sensor tables (background, vignetting, gains, ...) and its
// buffers, a few MB on a 240 x 320 profile, so they are neither built per frame nor kept for
// every instance. Not thread-safe (one per generator); non-copyable (profile_.name points into
// name_).
class RendererCache {
 public:
  static constexpr int kCapacity = 2;  // both fingers of an episode; a session plus one spare

  // Builds instance 0 at once, so a bad profile fails at generator creation.
  static Result<std::unique_ptr<RendererCache>> create(const SensorProfile& profile, uint64_t seed,
                                                       int32_t instances);
  RendererCache(const RendererCache&) = delete;
  RendererCache& operator=(const RendererCache&) = delete;

  // The Renderer of `instance` (0 <= instance < instances), built if it is not kept. The
  // pointer stays valid until the next get() of another instance.
  Result<Renderer*> get(int32_t instance);
  const SensorProfile& profile() const { return profile_; }
  int64_t builds() const { return builds_; }  // Renderers built so far (instance 0 included)

 private:
  RendererCache(const SensorProfile& profile, uint64_t seed, int32_t instances);
  struct Slot {
    int32_t instance = -1;
    uint64_t last_use = 0;
    std::unique_ptr<Renderer> renderer;
  };
  std::string name_;
  SensorProfile profile_;
  uint64_t seed_;
  int32_t instances_;
  std::array<Slot, kCapacity> slots_;
  uint64_t clock_ = 0;
  int64_t builds_ = 0;
};

}  // namespace tlvlink::sim::internal
