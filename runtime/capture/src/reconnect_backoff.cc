#include "tlvlink/capture/reconnect_backoff.h"

#include "tlvlink/clock.h"

namespace tlvlink::capture {

void ReconnectBackoff::lost(int64_t now_ns, bool streamed) {
  if (streamed || delay_ms_ == 0) {
    delay_ms_ = initial_ms_;
  } else {
    delay_ms_ = delay_ms_ > max_ms_ / 2 ? max_ms_ : delay_ms_ * 2;
  }
  if (!in_outage_) outage_start_ns_ = now_ns;
  in_outage_ = true;
  next_attempt_ns_ = now_ns + delay_ms_ * kNsPerMs;
}

void ReconnectBackoff::absent_at_start(int64_t now_ns) {
  delay_ms_ = initial_ms_;
  in_outage_ = true;
  outage_start_ns_ = now_ns;
  next_attempt_ns_ = now_ns;
}

void ReconnectBackoff::attempt_failed(int64_t now_ns) {
  delay_ms_ = delay_ms_ > max_ms_ / 2 ? max_ms_ : delay_ms_ * 2;
  if (delay_ms_ < initial_ms_) delay_ms_ = initial_ms_;
  next_attempt_ns_ = now_ns + delay_ms_ * kNsPerMs;
}

void ReconnectBackoff::reopened(int64_t now_ns) {
  if (!in_outage_) return;
  closed_outage_ns_ += now_ns - outage_start_ns_;
  in_outage_ = false;
}

void ReconnectBackoff::reset() {
  delay_ms_ = 0;
  in_outage_ = false;
  outage_start_ns_ = closed_outage_ns_ = next_attempt_ns_ = 0;
}

int64_t ReconnectBackoff::outage_ns(int64_t now_ns) const {
  return closed_outage_ns_ + current_outage_ns(now_ns);
}

int64_t ReconnectBackoff::current_outage_ns(int64_t now_ns) const {
  return in_outage_ ? now_ns - outage_start_ns_ : 0;
}

}  // namespace tlvlink::capture
