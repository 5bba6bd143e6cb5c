// listen::Client on a recording: the recorded bytes through the same decoder at their recorded
// times (optionally paced in real time), link events as recorded.
#include <thread>

#include "client_impl.h"
#include "tlvlink/transport/time.h"

namespace tlvlink::listen {

Status Client::Impl::pump_replay(int64_t deadline) {
  while (ready.empty() && !ended) {
    if (!pending_record) {
      Record r;
      TLV_ASSIGN_OR_RETURN(const bool more, replay->next(r));
      if (!more) {
        ended = true;
        event(LinkEvent::Kind::kEndOfRecording,
              replay->truncated() ? "end of recording (its last record was cut short)"
                                  : "end of recording",
              transport::monotonic_ns());
        return Status();
      }
      pending_record = std::move(r);
    }
    const Record& r = *pending_record;
    if (options.realtime) {
      const int64_t now = transport::monotonic_ns();
      if (!replay_started) replay_offset_ns = now - r.time_ns, replay_started = true;
      const int64_t due = r.time_ns + replay_offset_ns;
      if (due > now) {
        if (now >= deadline) return Status();
        std::this_thread::sleep_for(std::chrono::nanoseconds(std::min(due, deadline) - now));
        continue;
      }
    }
    switch (r.kind) {
      case RecordKind::kReceived: on_bytes(r.data, r.time_ns); break;
      case RecordKind::kLinkUp: {
        deframer->reset();
        version_reported = false;
        {
          std::lock_guard lock(mutex);
          ++stats.connects;
          stats.link_up = true;
        }
        event(LinkEvent::Kind::kConnected,
              std::string(reinterpret_cast<const char*>(r.data.data()), r.data.size()), r.time_ns);
        break;
      }
      case RecordKind::kLinkDown: {
        {
          std::lock_guard lock(mutex);
          ++stats.disconnects;
          stats.link_up = false;
        }
        event(LinkEvent::Kind::kDisconnected,
              std::string(reinterpret_cast<const char*>(r.data.data()), r.data.size()), r.time_ns);
        break;
      }
      case RecordKind::kSentAuto:
      case RecordKind::kSent:
        // The live client's commands: remember them as it did (its own ones' replies are
        // consumed; every one's Pong counts for the clock).
        sent_deframer->feed(r.data, [&](const protocol::ReceivedFrame& f) {
          if (f.verdict != protocol::FrameVerdict::kOk) return;
          if (r.kind == RecordKind::kSentAuto) note_internal(f.header.sequence);
          std::lock_guard lock(mutex);
          note_sent(f.header.sequence, f.header.send_ns);
        });
        break;
      default: break;  // a newer recorder's record kinds
    }
    // A replay copied into another container (`replay run.tlvrec --record run.mcap`).
    record(r.kind, r.time_ns, r.data);
    pending_record.reset();
    if (!options.realtime && transport::monotonic_ns() >= deadline) return Status();
  }
  return Status();
}

}  // namespace tlvlink::listen
