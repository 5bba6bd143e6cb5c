#include "output_queue.h"

#include <chrono>

namespace tlvlink::daemon::internal {

OutputQueue::OutputQueue(int32_t capacity)
    : storage_(static_cast<size_t>(capacity)), ring_(storage_) {}

void OutputQueue::push(const OutputRecord& record) {
  {
    std::lock_guard lock(mutex_);
    ring_.push(record);
  }
  cv_.notify_one();
}

bool OutputQueue::pop(OutputRecord& out, int32_t timeout_ms) {
  std::unique_lock lock(mutex_);
  cv_.wait_for(lock, std::chrono::milliseconds(timeout_ms),
               [&] { return !ring_.empty() || closed_; });
  return ring_.pop(out);
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
  return ring_.dropped();
}

size_t OutputQueue::size() const {
  std::lock_guard lock(mutex_);
  return ring_.size();
}

}  // namespace tlvlink::daemon::internal
