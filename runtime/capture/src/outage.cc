#include "tlvlink/capture/outage.h"

#include "tlvlink/clock.h"

namespace tlvlink::capture {

void begin_outage(const OutageBook& o, bool streamed) {
  const int64_t now = board_clock_ns();
  ++o.stats.disconnects;
  o.backoff.lost(now, streamed);
  o.stats.outage_ns = o.backoff.outage_ns(now);
}

Status reconnect_until(const OutageBook& o, const char* name, int64_t deadline_ns,
                       ReopenFn reopen) {
  for (;;) {
    int64_t now = board_clock_ns();
    if (o.backoff.due(now)) {
      Status st = reopen();
      now = board_clock_ns();
      if (st.ok()) {
        o.backoff.reopened(now);
        o.stats.outage_ns = o.backoff.outage_ns(now);
        ++o.stats.reconnects;
        return Status();
      }
      ++o.stats.reconnect_attempts;
      o.last_reopen_error = st.error();
      o.backoff.attempt_failed(now);
    }
    o.stats.outage_ns = o.backoff.outage_ns(now);
    if (o.backoff.next_attempt_ns() > deadline_ns) {
      sleep_until_ns(deadline_ns);
      now = board_clock_ns();
      o.stats.outage_ns = o.backoff.outage_ns(now);
      const char* reason = o.last_reopen_error.code() == ErrorCode::kOk
                               ? "not reopened yet"
                               : o.last_reopen_error.message();
      return Error::make(
          ErrorCode::kCaptureDisconnected,
          "%s: disconnected for %lld ms, %llu reopen attempts failed, next in %lld ms: %s", name,
          static_cast<long long>(o.backoff.current_outage_ns(now) / kNsPerMs),
          static_cast<unsigned long long>(o.stats.reconnect_attempts),
          static_cast<long long>((o.backoff.next_attempt_ns() - now) / kNsPerMs), reason);
    }
    sleep_until_ns(o.backoff.next_attempt_ns());
  }
}

void end_outage_at_stop(const OutageBook& o) {
  if (!o.backoff.in_outage()) return;
  const int64_t now = board_clock_ns();
  o.backoff.reopened(now);
  o.stats.outage_ns = o.backoff.outage_ns(now);
}

}  // namespace tlvlink::capture
