#include "frame_ring.h"

#include <chrono>
#include <climits>

namespace tlvlink::daemon::internal {

namespace {
// A producer waiting for the consumer sees the stop flag this soon.
constexpr auto kStopCheck = std::chrono::milliseconds(20);
}  // namespace

FrameRing::FrameRing(int32_t waiting, size_t frame_bytes, Doorbell& doorbell, WhenFull when_full)
    : when_full_(when_full),
      slots_(static_cast<size_t>(waiting) + 2),
      free_storage_(slots_.size(), nullptr),
      waiting_storage_(slots_.size(), nullptr),
      free_(free_storage_),
      waiting_(waiting_storage_),
      doorbell_(doorbell) {
  for (DecodedFrame& f : slots_) {
    f.rgb.assign(frame_bytes, 0);
    free_.push(&f);
  }
}

DecodedFrame* FrameRing::acquire(const std::atomic<bool>& stop) {
  std::unique_lock lock(mutex_);
  DecodedFrame* slot = nullptr;
  if (free_.pop(slot)) return slot;
  if (when_full_ == WhenFull::kWaitForConsumer) {
    while (!free_.pop(slot)) {
      if (stop.load()) return nullptr;
      slot_freed_.wait_for(lock, kStopCheck);
    }
    return slot;
  }
  // No free slot: the oldest waiting frame gives way.
  if (!waiting_.pop(slot)) return nullptr;  // cannot happen: one writer, one reader
  ++dropped_;
  return slot;
}

void FrameRing::publish(DecodedFrame* frame) {
  {
    std::lock_guard lock(mutex_);
    waiting_.push(frame);
  }
  {
    std::lock_guard lock(doorbell_.mutex);
    ++doorbell_.rings;
  }
  doorbell_.cv.notify_one();
}

void FrameRing::discard(DecodedFrame* frame) {
  std::lock_guard lock(mutex_);
  free_.push(frame);
}

DecodedFrame* FrameRing::take() {
  std::lock_guard lock(mutex_);
  DecodedFrame* slot = nullptr;
  return waiting_.pop(slot) ? slot : nullptr;
}

void FrameRing::recycle(DecodedFrame* frame) {
  {
    std::lock_guard lock(mutex_);
    free_.push(frame);
  }
  slot_freed_.notify_one();
}

int64_t FrameRing::oldest_capture_ns() {
  std::lock_guard lock(mutex_);
  return waiting_.empty() ? INT64_MAX : waiting_.front()->times.capture_ns;
}

uint64_t FrameRing::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

}  // namespace tlvlink::daemon::internal
