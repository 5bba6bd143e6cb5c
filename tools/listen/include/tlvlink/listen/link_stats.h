#pragma once
// What a host knows about its link: frames and rejections by cause, sequence gaps, reconnects,
// latencies. Kept by the Client; printed by `tlvlink listen`.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tlvlink/protocol/clock.h"
#include "tlvlink/protocol/deframer.h"

namespace tlvlink::listen {

// The last kCapacity samples of a latency, for percentiles.
class LatencyWindow {
 public:
  static constexpr size_t kCapacity = 8192;
  void add(int64_t ns);
  size_t count() const { return total_; }  // all samples ever added
  // p in [0, 100] over the samples in the window; 0 when empty.
  int64_t percentile(double p) const;
  int64_t max() const { return max_; }

 private:
  std::vector<int64_t> samples_;
  size_t next_ = 0, total_ = 0;
  int64_t max_ = 0;
};

struct LinkStats {
  protocol::DeframerCounters
      frames;             // bytes, good frames, rejected by verdict (accumulated over reconnects)
  uint64_t messages = 0;  // good frames of a known type, delivered or consumed
  uint64_t unknown_types = 0;    // good frames of a type this client does not know: skipped
  uint64_t undecodable = 0;      // good frames whose payload did not verify
  uint64_t sequence_gaps = 0;    // times the board's sequence jumped forward
  uint64_t frames_missing = 0;   // frames those jumps skipped (lost or rejected on the link)
  uint64_t sequence_resets = 0;  // the sequence went back (board restarted, or reordering)
  uint64_t board_restarts = 0;   // a Hello with a new boot id
  uint64_t delayed = 0;          // messages the board flagged as sent late
  uint64_t connects = 0, disconnects = 0;
  bool link_up = false;
  LatencyWindow link_latency;     // send -> receive, on the host clock (needs the clock estimate)
  LatencyWindow capture_latency;  // FramePrediction capture -> receive, on the host clock
  LatencyWindow round_trip;       // Pong delay (NTP delay)
  protocol::ClockEstimate clock;
};

}  // namespace tlvlink::listen
