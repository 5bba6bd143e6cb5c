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
    ring_.push(c);
  }
  wake();
}

void Completions::wake() {
  const uint64_t one = 1;
  [[maybe_unused]] ssize_t n = ::write(efd_, &one, sizeof(one));
}

bool Completions::pop(LibcameraCompletion& c) {
  std::lock_guard<std::mutex> lock(mu_);
  return ring_.pop(c);
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
  ring_.clear();
}

}  // namespace tlvlink::capture::internal
