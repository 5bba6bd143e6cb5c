// listen::Client: what every received frame does to the statistics, the clock and the queue of
// messages for the user.
#include <algorithm>

#include "client_impl.h"
#include "tlvlink/protocol/names.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::listen {

void Client::Impl::event(LinkEvent::Kind kind, std::string text, int64_t time_ns) {
  std::lock_guard lock(mutex);
  events.push_back(LinkEvent{kind, std::move(text), time_ns});
}

bool Client::Impl::is_internal(uint32_t sequence) const {
  return std::find(internal_sequences.begin(), internal_sequences.end(), sequence) !=
         internal_sequences.end();
}

void Client::Impl::note_internal(uint32_t sequence) {
  constexpr size_t kRemembered = 64;  // replies come back within a few; older ones are forgotten
  if (internal_sequences.size() == kRemembered)
    internal_sequences.erase(internal_sequences.begin());
  internal_sequences.push_back(sequence);
}

void Client::Impl::note_sent(uint32_t sequence, int64_t send_ns) {
  constexpr size_t kRemembered = 64;  // Pongs come back within a few commands
  if (sent_commands.size() == kRemembered) sent_commands.erase(sent_commands.begin());
  sent_commands.emplace_back(sequence, send_ns);
}

bool Client::Impl::sent_by_us(uint32_t sequence, int64_t send_ns) const {
  return std::find(sent_commands.begin(), sent_commands.end(), std::pair(sequence, send_ns)) !=
         sent_commands.end();
}

// Flushed per record: a recorder that is killed keeps everything it had received.
void Client::Impl::record(RecordKind kind, int64_t time_ns, std::span<const std::byte> data) {
  for (RecordSink* to : {static_cast<RecordSink*>(recorder.get()), sink}) {
    if (to == nullptr || record_error) continue;
    Status st = to->write(kind, time_ns, data);
    if (st.ok()) st = to->flush();
    if (!st.ok()) record_error = st.error();  // next() returns it; nothing more is recorded
  }
  if (record_error) recorder.reset(), sink = nullptr;
}

// The board's sequence: +1 per frame it sends; a jump forward is frames lost or rejected on the
// link, a jump back a restart (or reordering). Every good frame counts, known type or not.
void Client::Impl::track_sequence(uint32_t sequence) {
  if (have_sequence) {
    const uint32_t gap = sequence - (last_sequence + 1);
    if (gap != 0 && gap < 0x80000000u) {
      ++stats.sequence_gaps;
      stats.frames_missing += gap;
    } else if (gap != 0) {
      ++stats.sequence_resets;
    }
  }
  last_sequence = sequence, have_sequence = true;
}

void Client::Impl::on_bytes(std::span<const std::byte> bytes, int64_t receive_ns) {
  deframer->feed(bytes, [&](const protocol::ReceivedFrame& f) { on_frame(f, receive_ns); });
  std::lock_guard lock(mutex);
  stats.frames = deframer->counters();
}

void Client::Impl::on_frame(const protocol::ReceivedFrame& f, int64_t t) {
  using protocol::MessageType;
  if (f.verdict == protocol::FrameVerdict::kVersion) {
    if (!version_reported) {
      version_reported = true;
      char text[200];
      std::snprintf(text, sizeof(text),
                    "the board speaks stream protocol %u.%u; this client speaks %u.%u: its frames "
                    "are refused "
                    "(update the client or the board)",
                    f.header.version_major, f.header.version_minor, protocol::kVersionMajor,
                    protocol::kVersionMinor);
      event(LinkEvent::Kind::kVersionMismatch, text, t);
    }
    return;
  }
  if (f.verdict != protocol::FrameVerdict::kOk) return;
  const char* type_name = protocol::message_type_name(f.header.type);
  std::unique_lock lock(mutex);
  // A Hello with a new boot id restarts the board's sequence: judge gaps after looking at it.
  const bool is_hello = f.header.type == MessageType::kHello;
  if (!is_hello) track_sequence(f.header.sequence);
  if (type_name == nullptr || f.header.type == MessageType::kCommand) {
    ++stats.unknown_types;  // a newer board's message, or something not meant for a host: skipped
    return;
  }
  if (!protocol::verify_payload(f.header.type, f.payload).ok()) {
    ++stats.undecodable;
    return;
  }
  ++stats.messages;
  if (f.header.flags & protocol::kFlagDelayed) ++stats.delayed;
  Message m(f.header, f.payload, t);
  bool deliver = true;
  if (is_hello) {
    const uint64_t boot = m.hello().value().boot_id();
    if (have_boot_id && boot != boot_id) {
      ++stats.board_restarts;
      clock.reset();
      have_sequence = false;
      lock.unlock();
      event(LinkEvent::Kind::kBoardRestarted, "the board restarted (new boot id)", t);
      lock.lock();
    }
    boot_id = boot, have_boot_id = true;
    hello = m;
    info_due_ns = 0;  // greeted: no need to ask
    track_sequence(f.header.sequence);
  }
  if (f.header.type == MessageType::kPong) {
    const protocol::Pong p = m.pong().value();
    if (sent_by_us(p.command_sequence, p.host_send_ns) &&
        clock.add({p.host_send_ns, p.board_receive_ns, f.header.send_ns, t})) {
      stats.round_trip.add((t - p.host_send_ns) - (f.header.send_ns - p.board_receive_ns));
    }
    deliver = !is_internal(p.command_sequence);
  } else if (f.header.type == MessageType::kAck) {
    deliver = !is_internal(m.ack().value().command_sequence);
  } else if (f.header.type == MessageType::kNack) {
    deliver = !is_internal(m.nack().value().command_sequence);
  }
  stats.clock = clock.estimate(t);
  m.set_clock(stats.clock);
  if (stats.clock.valid) {
    stats.link_latency.add(t - clock.board_to_host(f.header.send_ns));
    if (f.header.type == MessageType::kFramePrediction) {
      stats.capture_latency.add(
          t - clock.board_to_host(m.frame_prediction().value().timing().capture_ns));
    }
  }
  if (deliver) ready.push_back(std::move(m));
}

}  // namespace tlvlink::listen
