// listen::Client on a live link: open with backoff, Info and TimeSync at connect, TimeSync once
// a period, commands out, bytes in.
#include <algorithm>
#include <thread>

#include "client_impl.h"
#include "tlvlink/protocol/encode.h"
#include "tlvlink/transport/time.h"

namespace tlvlink::listen {
namespace {
constexpr int kBurstSyncs = 3;  // quick TimeSyncs after a connect: a good estimate at once
constexpr int64_t kBurstGapNs = 50'000'000;
constexpr int64_t kInfoAfterNs = 300'000'000;
}  // namespace

using transport::monotonic_ns;

void Client::Impl::on_connected() {
  const int64_t now = monotonic_ns();
  deframer->reset();
  backoff_ms = options.reconnect_min_ms;
  version_reported = false;
  {
    std::lock_guard lock(mutex);
    ++stats.connects;
    stats.link_up = true;
    // Commands queued for a link that went away are dropped with it.
    out_user.clear();
    out_auto.clear();
  }
  const std::string name(link->name());
  record(RecordKind::kLinkUp, now, std::as_bytes(std::span(name.data(), name.size())));
  event(LinkEvent::Kind::kConnected, name, now);
  // A board greets every new connection with a Hello; a client joining a link the board did not
  // see go down (a reader restarted on CDC-ACM) gets none: it asks if none came by then.
  info_due_ns = options.request_info ? now + kInfoAfterNs : 0;
  next_sync_ns = now;
  burst_syncs = options.time_sync_ms > 0 ? kBurstSyncs : 0;
}

void Client::Impl::on_disconnected(const Error& why) {
  const int64_t now = monotonic_ns();
  link->close();
  {
    std::lock_guard lock(mutex);
    ++stats.disconnects;
    stats.link_up = false;
  }
  const std::string text = why.message();
  record(RecordKind::kLinkDown, now, std::as_bytes(std::span(text.data(), text.size())));
  event(LinkEvent::Kind::kDisconnected, text, now);
  down_reason = text;
  next_open_ns = now + int64_t{options.reconnect_min_ms} * 1'000'000;
}

Status Client::Impl::queue_own(const protocol::Command& command) {
  alignas(8) static thread_local std::byte scratch[protocol::kEncodeBufferSize];
  static thread_local std::byte wire[protocol::kMaxWireFrameSize];
  std::lock_guard lock(mutex);
  protocol::FrameHeader h;
  h.sequence = next_sequence++;
  h.send_ns = monotonic_ns();
  TLV_ASSIGN_OR_RETURN(const size_t n, protocol::encode_message(command, h, scratch, wire));
  out_auto.insert(out_auto.end(), wire, wire + n);
  note_internal(h.sequence);
  note_sent(h.sequence, h.send_ns);
  return Status();
}

Status Client::Impl::write_pending() {
  std::lock_guard lock(mutex);
  const bool user = !out_user.empty();
  std::vector<std::byte>& out = user ? out_user : out_auto;
  if (out.empty()) return Status();
  TLV_ASSIGN_OR_RETURN(const size_t n, link->write(out));
  if (n == 0) return Status();
  record(user ? RecordKind::kSent : RecordKind::kSentAuto, monotonic_ns(), std::span(out).first(n));
  out.erase(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n));
  return Status();
}

Status Client::Impl::pump_live(int64_t deadline) {
  std::byte buf[4096];
  while (ready.empty()) {
    int64_t now = monotonic_ns();
    if (now >= deadline) return Status();
    if (!link->is_open()) {
      if (now < next_open_ns) {
        std::this_thread::sleep_for(
            std::chrono::nanoseconds(std::min(deadline, next_open_ns) - now));
        continue;
      }
      Status opened = link->open();
      if (!opened.ok()) {
        if (!options.reconnect) return opened.error();
        if (down_reason != opened.error().message()) {  // report each new reason once
          down_reason = opened.error().message();
          event(LinkEvent::Kind::kDisconnected, down_reason, now);
        }
        next_open_ns = now + int64_t{backoff_ms} * 1'000'000;
        backoff_ms = std::min(2 * backoff_ms, options.reconnect_max_ms);
        continue;
      }
      on_connected();
    }
    if (info_due_ns != 0 && now >= info_due_ns) {
      info_due_ns = 0;
      protocol::Command info;
      info.kind = protocol::CommandKind::kInfo;
      (void)queue_own(info);
    }
    if (options.time_sync_ms > 0 && now >= next_sync_ns) {
      protocol::Command sync;
      sync.kind = protocol::CommandKind::kTimeSync;
      {
        std::lock_guard lock(mutex);
        const protocol::ClockEstimate e = clock.estimate(now);
        if (e.valid)
          sync.clock_offset_ns = e.offset_ns,
          sync.clock_uncertainty_ns = std::max<int64_t>(1, e.uncertainty_ns);
      }
      (void)queue_own(sync);
      next_sync_ns =
          now + (burst_syncs > 0 ? kBurstGapNs : int64_t{options.time_sync_ms} * 1'000'000);
      if (burst_syncs > 0) --burst_syncs;
    }
    bool want_write;
    {
      std::lock_guard lock(mutex);
      want_write = !out_user.empty() || !out_auto.empty();
    }
    int64_t until = deadline;
    if (options.time_sync_ms > 0) until = std::min(until, next_sync_ns);
    if (info_due_ns != 0) until = std::min(until, info_due_ns);
    const int wait_ms =
        static_cast<int>(std::clamp<int64_t>((until - now + 999'999) / 1'000'000, 0, 1000));
    Result<transport::Readiness> r = link->wait(want_write, wait_ms);
    if (!r.ok()) {
      if (!options.reconnect) return r.error();
      on_disconnected(r.error());
      continue;
    }
    if (r.value().readable) {
      Result<size_t> n = link->read(buf);
      if (!n.ok()) {
        if (!options.reconnect) return n.error();
        on_disconnected(n.error());
        continue;
      }
      if (n.value() > 0) {
        const int64_t t = monotonic_ns();
        record(RecordKind::kReceived, t, std::span<const std::byte>(buf, n.value()));
        on_bytes(std::span<const std::byte>(buf, n.value()), t);
      }
    }
    if (want_write && r.value().writable) {
      Status w = write_pending();
      if (!w.ok()) {
        if (!options.reconnect) return w.error();
        on_disconnected(w.error());
      }
    }
  }
  return Status();
}

}  // namespace tlvlink::listen
