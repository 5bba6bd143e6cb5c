#pragma once
// The reconnect schedule and outage clock every camera source shares. Pure logic: the caller
// passes CLOCK_MONOTONIC times in, so it is tested with a fake clock. No I/O, no allocation.
//
//   lost(now, streamed)   the device went away (or stalled): an outage begins, the first reopen is
//                         due one delay later
//   due(now)              a reopen attempt may be made now
//   attempt_failed(now)   the delay doubles, up to max_ms
//   reopened(now)         the outage ends; its duration is added to the total
//
// The delay restarts at initial_ms only when the device had delivered a frame since it was last
// opened. A device that opens but never streams — an HDMI input without signal, a node that fails
// at once after STREAMON, a stall before the first frame — keeps the grown delay, so an
// open/fail cycle is paced by the backoff (up to max_ms apart) instead of restarting every
// initial_ms.

#include <cstdint>

namespace tlvlink::capture {

class ReconnectBackoff {
 public:
  // 0 < initial_ms <= max_ms (checked by the sources' configuration).
  ReconnectBackoff(int32_t initial_ms, int32_t max_ms) : initial_ms_(initial_ms), max_ms_(max_ms) {}

  // An outage begins at now_ns. `streamed`: the device delivered a frame since its last open.
  void lost(int64_t now_ns, bool streamed);
  // The device was absent at start(): an outage from the start, the first attempt due at once.
  void absent_at_start(int64_t now_ns);
  // A reopen attempt failed at now_ns: the next one is due after the doubled delay.
  void attempt_failed(int64_t now_ns);
  // A reopen succeeded at now_ns: the outage is over.
  void reopened(int64_t now_ns);
  // start() again: no outage, no history.
  void reset();

  bool in_outage() const { return in_outage_; }
  bool due(int64_t now_ns) const { return in_outage_ && now_ns >= next_attempt_ns_; }
  int64_t next_attempt_ns() const { return next_attempt_ns_; }
  int32_t delay_ms() const { return delay_ms_; }
  // Time without a device: every outage so far, the current one up to now_ns included.
  int64_t outage_ns(int64_t now_ns) const;
  // The current outage's length at now_ns (0 when connected).
  int64_t current_outage_ns(int64_t now_ns) const;

 private:
  int32_t initial_ms_, max_ms_;
  int32_t delay_ms_ = 0;  // the delay before the next attempt (0: no outage yet)
  bool in_outage_ = false;
  int64_t outage_start_ns_ = 0;
  int64_t closed_outage_ns_ = 0;  // outages already over
  int64_t next_attempt_ns_ = 0;
};

}  // namespace tlvlink::capture
