#include "gen/sensor_instances.h"

#include "gen/rng.h"
#include "tlvlink/sim/generate.h"

namespace tlvlink::sim {

uint64_t sensor_instance_seed(uint64_t seed, int32_t instance) {
  // Instance 0 keeps the seed every set used before there were several instances, so sets with
  // one instance keep their bytes.
  const uint64_t sensor = internal::tag(internal::Stream::kSensor);
  return instance == 0 ? internal::derive_seed(seed, {sensor})
                       : internal::derive_seed(seed, {sensor, static_cast<uint64_t>(instance)});
}

namespace internal {

// The modulo bias is below instances / 2^64 < 2^-47: negligible.
int32_t touch_session_instance(uint64_t seed, int64_t session, int32_t instances) {
  if (instances <= 1) return 0;
  return static_cast<int32_t>(
      derive_seed(seed, {tag(Stream::kSensorInstance), static_cast<uint64_t>(session)}) %
      static_cast<uint64_t>(instances));
}

int32_t grasp_finger_instance(uint64_t seed, int64_t episode, int32_t finger, int32_t instances) {
  if (instances <= 1) return 0;
  return static_cast<int32_t>(
      derive_seed(seed, {tag(Stream::kSensorInstance), static_cast<uint64_t>(episode),
                         static_cast<uint64_t>(finger)}) %
      static_cast<uint64_t>(instances));
}

RendererCache::RendererCache(const SensorProfile& profile, uint64_t seed, int32_t instances)
    : name_(profile.name), profile_(profile), seed_(seed), instances_(instances) {
  profile_.name = name_;  // the caller's string may not outlive us
}

Result<std::unique_ptr<RendererCache>> RendererCache::create(const SensorProfile& profile,
                                                             uint64_t seed, int32_t instances) {
  TLV_ENSURE(instances >= 1 && instances <= kMaxSensorInstances, ErrorCode::kInvalidArgument,
             "sensor_instances = %d is outside 1..%d", instances, kMaxSensorInstances);
  std::unique_ptr<RendererCache> cache(new RendererCache(profile, seed, instances));
  TLV_TRY(cache->get(0));
  return cache;
}

Result<Renderer*> RendererCache::get(int32_t instance) {
  TLV_ENSURE(instance >= 0 && instance < instances_, ErrorCode::kInvalidArgument,
             "sensor instance %d is outside 0..%d", instance, instances_ - 1);
  ++clock_;
  Slot* victim = &slots_[0];
  for (Slot& s : slots_) {
    if (s.renderer && s.instance == instance) {
      s.last_use = clock_;
      return s.renderer.get();
    }
    if (!s.renderer || (victim->renderer && s.last_use < victim->last_use)) victim = &s;
  }
  // Free the evicted one first: two sets of tables never coexist beyond kCapacity.
  victim->renderer.reset();
  victim->instance = -1;
  TLV_ASSIGN_OR_RETURN(victim->renderer,
                       Renderer::create(profile_, sensor_instance_seed(seed_, instance)));
  victim->instance = instance;
  victim->last_use = clock_;
  ++builds_;
  return victim->renderer.get();
}

}  // namespace internal
}  // namespace tlvlink::sim
