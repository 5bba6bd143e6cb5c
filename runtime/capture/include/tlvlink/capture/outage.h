#pragma once
// The outage a camera source goes through when its device goes away, and the bounded reopening
// while it is gone: one loop for every source (V4L2, libcamera), on the board clock
// (tlvlink/clock.h; tests drive it with a FakeClock). The schedule is ReconnectBackoff's.

#include <cstdint>

#include "tlvlink/capture/frame_source.h"
#include "tlvlink/capture/reconnect_backoff.h"
#include "tlvlink/error.h"

namespace tlvlink::capture {

// A source's outage bookkeeping, borrowed for the call.
struct OutageBook {
  ReconnectBackoff& backoff;
  SourceStats& stats;        // disconnects, reconnects, reconnect_attempts, outage_ns
  Error& last_reopen_error;  // why the last reopen failed (kOk: none failed yet)
};

// What reconnect_until() calls to reopen the device (Ok: streaming again). Borrows `f`.
class ReopenFn {
 public:
  template <typename F>
  ReopenFn(F& f)  // NOLINT: implicit, so a lambda is passed as it is
      : context_(&f), call_([](void* c) -> Status { return (*static_cast<F*>(c))(); }) {}
  Status operator()() const { return call_(context_); }

 private:
  void* context_;
  Status (*call_)(void*);
};

// The device is gone (its stream already closed by the caller): counts the outage and starts
// the backoff. `streamed`: it had delivered a frame since it was opened (the delay restarts).
void begin_outage(const OutageBook& o, bool streamed);

// While disconnected: reopen attempts when the backoff allows, until deadline_ns; between them
// the thread sleeps, so a caller calling next() in a loop waits its timeout per call (no
// spinning). Ok once reopened; otherwise kCaptureDisconnected: "NAME: disconnected for N ms, N
// reopen attempts failed, next in N ms: <the last reopen error, or 'not reopened yet'>".
Status reconnect_until(const OutageBook& o, const char* name, int64_t deadline_ns, ReopenFn reopen);

// stop() during an outage: the outage's clock stops with the source.
void end_outage_at_stop(const OutageBook& o);

}  // namespace tlvlink::capture
