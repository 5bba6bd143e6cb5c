// Stats: the board's heartbeat (rates, drops by cause, CPU, link counters).
#include <array>

#include "protocol_internal.h"

namespace tlvlink::protocol {
namespace {
namespace fb = tlvlink::wire;
}  // namespace

Result<std::span<const std::byte>> encode_payload(const Stats& m, std::span<std::byte> buffer) {
  constexpr const char* kWhat = "Stats";
  TLV_TRY(internal::check_list(kWhat, "sensors", m.sensors.size()));
  TLV_TRY(internal::check_list(kWhat, "drops", m.drops.size()));
  internal::SizeBound bound;
  bound.table(7);
  bound.table(9);  // LinkStats
  bound.vector(m.sensors.size(), 4);
  for (size_t i = 0; i < m.sensors.size(); ++i) bound.table(5);
  bound.vector(m.drops.size(), 4);
  for (size_t i = 0; i < m.drops.size(); ++i) bound.table(3);
  return internal::build_payload(kWhat, bound, buffer, [&](flatbuffers::FlatBufferBuilder& fbb) {
    std::array<flatbuffers::Offset<fb::SensorStats>, kMaxListLength> sensors;
    for (size_t i = 0; i < m.sensors.size(); ++i) {
      const SensorStats& s = m.sensors[i];
      sensors[i] = fb::CreateSensorStats(fbb, s.sensor, s.fps, s.frames, s.inferred, s.gated);
    }
    std::array<flatbuffers::Offset<fb::DropCount>, kMaxListLength> drops;
    for (size_t i = 0; i < m.drops.size(); ++i) {
      const DropCount& d = m.drops[i];
      drops[i] = fb::CreateDropCount(fbb, static_cast<fb::DropCause>(d.cause), d.count, d.sensor);
    }
    flatbuffers::Offset<flatbuffers::Vector<flatbuffers::Offset<fb::SensorStats>>> sensor_vec;
    if (!m.sensors.empty()) sensor_vec = fbb.CreateVector(sensors.data(), m.sensors.size());
    flatbuffers::Offset<flatbuffers::Vector<flatbuffers::Offset<fb::DropCount>>> drop_vec;
    if (!m.drops.empty()) drop_vec = fbb.CreateVector(drops.data(), m.drops.size());
    const LinkStats& l = m.link;
    const auto link = fb::CreateLinkStats(fbb, l.link_up, l.reconnects, l.frames_sent, l.bytes_sent,
                                          l.frames_received, l.frames_rejected, l.queue_messages,
                                          l.queue_bytes, l.queue_capacity_bytes);
    fb::StatsBuilder b(fbb);
    b.add_uptime_ns(m.uptime_ns);
    b.add_sensors(sensor_vec);
    b.add_drops(drop_vec);
    b.add_cpu_percent(m.cpu_percent);
    b.add_cpu_cores(m.cpu_cores);
    b.add_rss_bytes(m.rss_bytes);
    b.add_link(link);
    return b.Finish();
  });
}

}  // namespace tlvlink::protocol
