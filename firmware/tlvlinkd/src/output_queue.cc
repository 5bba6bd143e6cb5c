#include "output_queue.h"

#include <chrono>

namespace tlvlink::daemon::internal {

OutputQueue::OutputQueue(int32_t capacity, bool wait_when_full)
    : wait_when_full_(wait_when_full), storage_(static_cast<size_t>(capacity)), ring_(storage_) {}

void OutputQueue::push(const OutputRecord& record) {
  {
    std::unique_lock lock(mutex_);
    // The output thread pops until the session stops it, after every producer has stopped.
    if (wait_when_full_) room_.wait(lock, [&] { return !ring_.full(); });
    ring_.push(record);
  }
  cv_.notify_one();
}

bool OutputQueue::pop(OutputRecord& out, int32_t timeout_ms) {
  bool popped = false;
  {
    std::unique_lock lock(mutex_);
    cv_.wait_for(lock, std::chrono::milliseconds(timeout_ms),
                 [&] { return !ring_.empty() || closed_; });
    popped = ring_.pop(out);
  }
  if (popped && wait_when_full_) room_.notify_all();
  return popped;
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
