#include "output_queue.h"

#include <chrono>

namespace tlvlink::daemon::internal {

OutputQueue::OutputQueue(int32_t capacity) : ring_(static_cast<size_t>(capacity)) {}

void OutputQueue::push(const OutputRecord& record) {
  {
    std::lock_guard lock(mutex_);
    if (count_ == ring_.size()) {
      head_ = (head_ + 1) % ring_.size();
      --count_;
      ++dropped_;
    }
    ring_[(head_ + count_) % ring_.size()] = record;
    ++count_;
  }
  cv_.notify_one();
}

bool OutputQueue::pop(OutputRecord& out, int32_t timeout_ms) {
  std::unique_lock lock(mutex_);
  cv_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [&] { return count_ > 0 || closed_; });
  if (count_ == 0) return false;
  out = ring_[head_];
  head_ = (head_ + 1) % ring_.size();
  --count_;
  return true;
}

void OutputQueue::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  cv_.notify_all();
}

uint64_t OutputQueue::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

size_t OutputQueue::size() const {
  std::lock_guard lock(mutex_);
  return count_;
}

}  // namespace tlvlink::daemon::internal
