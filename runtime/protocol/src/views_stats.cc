#include "protocol_internal.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::protocol {
namespace {
namespace fb = tlvlink::wire;
const fb::Stats* stats(const void* t) { return static_cast<const fb::Stats*>(t); }
}  // namespace

int64_t StatsView::uptime_ns() const { return stats(table_)->uptime_ns(); }
size_t StatsView::sensor_count() const {
  const auto* v = stats(table_)->sensors();
  return v ? v->size() : 0;
}
SensorStats StatsView::sensor(size_t i) const {
  const fb::SensorStats* s = stats(table_)->sensors()->Get(static_cast<flatbuffers::uoffset_t>(i));
  return SensorStats{s->sensor(), s->fps(), s->frames(), s->inferred(), s->gated()};
}
size_t StatsView::drop_count() const {
  const auto* v = stats(table_)->drops();
  return v ? v->size() : 0;
}
DropCount StatsView::drop(size_t i) const {
  const fb::DropCount* d = stats(table_)->drops()->Get(static_cast<flatbuffers::uoffset_t>(i));
  return DropCount{static_cast<DropCause>(d->cause()), d->count(), d->sensor()};
}
float StatsView::cpu_percent() const { return stats(table_)->cpu_percent(); }
uint8_t StatsView::cpu_cores() const { return stats(table_)->cpu_cores(); }
uint64_t StatsView::rss_bytes() const { return stats(table_)->rss_bytes(); }
LinkStats StatsView::link() const {
  LinkStats out;
  if (const fb::LinkStats* l = stats(table_)->link()) {
    out.link_up = l->link_up();
    out.reconnects = l->reconnects();
    out.frames_sent = l->frames_sent();
    out.bytes_sent = l->bytes_sent();
    out.frames_received = l->frames_received();
    out.frames_rejected = l->frames_rejected();
    out.queue_messages = l->queue_messages();
    out.queue_bytes = l->queue_bytes();
    out.queue_capacity_bytes = l->queue_capacity_bytes();
  }
  return out;
}

Result<StatsView> decode_stats(std::span<const std::byte> payload) {
  TLV_ASSIGN_OR_RETURN(const fb::Stats* root, internal::verified_root<fb::Stats>("Stats", payload));
  return StatsView(root);
}

}  // namespace tlvlink::protocol
