#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "output_queue.h is internal to firmware/tlvlinkd"
#endif
// Records on their way to the output thread: a fixed ring (core's DropOldestRing over storage
// allocated at start). With a camera it never blocks the producers (inference, capture events):
// when full, the oldest record is dropped and counted, so a slow link or file costs old records,
// never inference. When every source is a replay read as fast as it is processed, nothing has a
// pace to keep: a producer waits for room instead, and no record is lost.

#include <array>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <variant>
#include <vector>

#include "tlvlink/drop_oldest_ring.h"
#include "tlvlink/pipeline/predictions.h"

namespace tlvlink::daemon::internal {

// Something that happened (a camera outage and its end, a decode error, a reload): logged and
// written to the output stream.
struct EventRecord {
  int64_t t_ns = 0;
  int32_t sensor = -1;  // -1: the daemon
  bool error = false;
  std::array<char, 256> text{};
};

using OutputRecord =
    std::variant<pipeline::FramePrediction, pipeline::GraspPrediction, EventRecord>;

class OutputQueue {
 public:
  // wait_when_full: push waits for room (the output thread drains until the session stops).
  explicit OutputQueue(int32_t capacity, bool wait_when_full = false);

  void push(const OutputRecord& record);  // never blocks unless wait_when_full
  // Waits up to timeout_ms for a record; false when none came (or the queue was closed and is
  // empty).
  bool pop(OutputRecord& out, int32_t timeout_ms);
  void close();  // wakes the consumer; pushes after close are still accepted until drained

  uint64_t dropped() const;
  size_t size() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable cv_, room_;
  const bool wait_when_full_;
  std::vector<OutputRecord> storage_;
  DropOldestRing<OutputRecord> ring_;
  bool closed_ = false;
};

}  // namespace tlvlink::daemon::internal
