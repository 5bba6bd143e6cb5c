#include "frame_ring.h"

#include <climits>

namespace tlvlink::daemon::internal {

FrameRing::FrameRing(int32_t waiting, size_t frame_bytes, Doorbell& doorbell)
    : slots_(static_cast<size_t>(waiting) + 2),
      state_(slots_.size(), State::kFree),
      order_(slots_.size(), 0),
      doorbell_(doorbell) {
  for (DecodedFrame& f : slots_) f.rgb.assign(frame_bytes, 0);
}

DecodedFrame* FrameRing::acquire() {
  std::lock_guard lock(mutex_);
  for (size_t i = 0; i < slots_.size(); ++i) {
    if (state_[i] == State::kFree) {
      state_[i] = State::kWriting;
      return &slots_[i];
    }
  }
  // No free slot: the oldest waiting frame gives way.
  size_t oldest = slots_.size();
  for (size_t i = 0; i < slots_.size(); ++i) {
    if (state_[i] == State::kWaiting && (oldest == slots_.size() || order_[i] < order_[oldest]))
      oldest = i;
  }
  if (oldest == slots_.size()) return nullptr;  // cannot happen: one writer, one reader
  ++dropped_;
  state_[oldest] = State::kWriting;
  return &slots_[oldest];
}

void FrameRing::publish(DecodedFrame* frame) {
  {
    std::lock_guard lock(mutex_);
    const auto i = static_cast<size_t>(frame - slots_.data());
    state_[i] = State::kWaiting;
    order_[i] = ++published_;
  }
  {
    std::lock_guard lock(doorbell_.mutex);
    ++doorbell_.rings;
  }
  doorbell_.cv.notify_one();
}

void FrameRing::discard(DecodedFrame* frame) {
  std::lock_guard lock(mutex_);
  state_[static_cast<size_t>(frame - slots_.data())] = State::kFree;
}

DecodedFrame* FrameRing::take() {
  std::lock_guard lock(mutex_);
  size_t oldest = slots_.size();
  for (size_t i = 0; i < slots_.size(); ++i) {
    if (state_[i] == State::kWaiting && (oldest == slots_.size() || order_[i] < order_[oldest]))
      oldest = i;
  }
  if (oldest == slots_.size()) return nullptr;
  state_[oldest] = State::kReading;
  return &slots_[oldest];
}

void FrameRing::recycle(DecodedFrame* frame) {
  std::lock_guard lock(mutex_);
  state_[static_cast<size_t>(frame - slots_.data())] = State::kFree;
}

int64_t FrameRing::oldest_capture_ns() {
  std::lock_guard lock(mutex_);
  int64_t best = INT64_MAX;
  uint64_t best_order = UINT64_MAX;
  for (size_t i = 0; i < slots_.size(); ++i) {
    if (state_[i] == State::kWaiting && order_[i] < best_order) {
      best_order = order_[i];
      best = slots_[i].times.capture_ns;
    }
  }
  return best;
}

uint64_t FrameRing::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

}  // namespace tlvlink::daemon::internal
