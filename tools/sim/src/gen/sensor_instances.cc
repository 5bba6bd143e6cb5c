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

std::vector<std::string> profile_names(std::string_view sensor) {
  std::vector<std::string> out;
  while (true) {
    const size_t comma = sensor.find(',');
    out.emplace_back(sensor.substr(0, comma));
    if (comma == std::string_view::npos) break;
    sensor.remove_prefix(comma + 1);
  }
  return out;
}

size_t item_profile(uint64_t seed, int64_t item, size_t profiles) {
  if (profiles <= 1) return 0;
  return static_cast<size_t>(
      derive_seed(seed, {tag(Stream::kSensorProfile), static_cast<uint64_t>(item)}) % profiles);
}

namespace {
bool item_drawn(uint64_t seed, Stream stream, int64_t item, double fraction) {
  if (!(fraction > 0)) return false;
  const uint64_t h = derive_seed(seed, {tag(stream), static_cast<uint64_t>(item)});
  return static_cast<double>(h >> 11) * 0x1.0p-53 < fraction;
}
}  // namespace

bool item_has_markers(uint64_t seed, int64_t item, double fraction) {
  return item_drawn(seed, Stream::kMarkers, item, fraction);
}

bool item_takes_live_path(uint64_t seed, int64_t item, double fraction) {
  return item_drawn(seed, Stream::kLivePath, item, fraction);
}

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
