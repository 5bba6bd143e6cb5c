#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "frame_ring.h is internal to firmware/tlvlinkd"
#endif
// Decoded frames of one sensor on their way from its capture thread to the inference thread: a
// fixed set of slots (allocated at start). For a camera the producer never blocks: when every
// slot holds a frame not yet taken, the oldest waiting one is recycled and counted as dropped, so
// the capture thread keeps up with the camera whatever the consumer does. A replay read as fast
// as it is processed (realtime = false) has no pace to keep: its producer waits for a free slot
// instead, and every frame is processed. The waiting frames are a DropOldestRing of slots
// (tlvlink/drop_oldest_ring.h), the free ones another.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <vector>

#include "tlvlink/drop_oldest_ring.h"
#include "tlvlink/pipeline/predictions.h"

namespace tlvlink::daemon::internal {

struct DecodedFrame {
  std::vector<uint8_t> rgb;  // the processed frame, view.width * view.height * 3
  uint64_t sequence = 0;
  pipeline::FrameTimes times;
};

// Wakes the inference thread when any sensor publishes (one for all rings).
struct Doorbell {
  std::mutex mutex;
  std::condition_variable cv;
  uint64_t rings = 0;  // publishes since the consumer last looked
};

// What the producer does when every slot is taken.
enum class WhenFull : uint8_t { kDropOldest, kWaitForConsumer };

class FrameRing {
 public:
  // `waiting` frames may wait; two more slots are being written and read.
  FrameRing(int32_t waiting, size_t frame_bytes, Doorbell& doorbell,
            WhenFull when_full = WhenFull::kDropOldest);

  // Producer: a slot to write into. kDropOldest never blocks (it may recycle the oldest waiting
  // frame); kWaitForConsumer waits for the consumer to give one back, and returns nullptr once
  // `stop` is set.
  DecodedFrame* acquire(const std::atomic<bool>& stop);
  void publish(DecodedFrame* frame);  // the slot from acquire(), now filled
  void discard(DecodedFrame* frame);  // the slot from acquire(), not filled (decode failed)

  // Consumer: the oldest waiting frame, or nullptr; give it back with recycle().
  DecodedFrame* take();
  void recycle(DecodedFrame* frame);
  // Capture time of the oldest waiting frame, or INT64_MAX when none (to merge sensors in time).
  int64_t oldest_capture_ns();

  uint64_t dropped() const;  // frames recycled before the consumer took them

 private:
  mutable std::mutex mutex_;
  std::condition_variable slot_freed_;  // kWaitForConsumer's producer waits on it
  WhenFull when_full_;
  std::vector<DecodedFrame> slots_;
  // Slots not being written or read: free ones, and waiting ones oldest first. Each holds every
  // slot at most once, so neither ever overflows.
  std::vector<DecodedFrame*> free_storage_, waiting_storage_;
  DropOldestRing<DecodedFrame*> free_, waiting_;
  uint64_t dropped_ = 0;
  Doorbell& doorbell_;
};

}  // namespace tlvlink::daemon::internal
