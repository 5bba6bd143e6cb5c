#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>

#include "libcamera/libcamera_internal.h"

namespace tlvlink::capture::internal {

Completions::Completions() : efd_(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)) {}

Completions::~Completions() {
  if (efd_ >= 0) ::close(efd_);
}

void Completions::push(const LibcameraCompletion& c) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    // At most one completion per buffer is outstanding; a full ring means a buffer completed
    // twice without a requeue, which libcamera does not do: keep the newest.
    if (count_ == kMaxCompletions) {
      head_ = (head_ + 1) % kMaxCompletions;
      --count_;
    }
    ring_[(head_ + count_) % kMaxCompletions] = c;
    ++count_;
  }
  wake();
}

void Completions::wake() {
  const uint64_t one = 1;
  [[maybe_unused]] ssize_t n = ::write(efd_, &one, sizeof(one));
}

bool Completions::pop(LibcameraCompletion& c) {
  std::lock_guard<std::mutex> lock(mu_);
  if (count_ == 0) return false;
  c = ring_[head_];
  head_ = (head_ + 1) % kMaxCompletions;
  --count_;
  return true;
}

bool Completions::wait(int timeout_ms) {
  pollfd p{efd_, POLLIN, 0};
  int rc;
  do rc = ::poll(&p, 1, timeout_ms);
  while (rc < 0 && errno == EINTR);
  if (rc <= 0) return false;
  uint64_t value = 0;
  [[maybe_unused]] ssize_t n = ::read(efd_, &value, sizeof(value));
  return true;
}

void Completions::clear() {
  std::lock_guard<std::mutex> lock(mu_);
  head_ = count_ = 0;
}

}  // namespace tlvlink::capture::internal
