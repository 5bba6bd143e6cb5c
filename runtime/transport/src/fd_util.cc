#include "fd_util.h"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>

namespace tlvlink::transport::internal {

int make_wake_fd() { return eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC); }

void signal_wake_fd(int fd) {
  if (fd < 0) return;
  const uint64_t one = 1;
  // A full counter (2^64 - 2 pending wake-ups) already wakes the waiter: ignore EAGAIN.
  (void)!::write(fd, &one, sizeof(one));
}

void drain_wake_fd(int fd) {
  if (fd < 0) return;
  uint64_t value;
  (void)!::read(fd, &value, sizeof(value));
}

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

bool is_disconnect_errno(int err) {
  return err == EIO || err == ENODEV || err == ENXIO || err == EPIPE || err == ESHUTDOWN ||
         err == ECONNRESET || err == EBADF || err == ENOENT;
}

Error open_error(std::string_view what, std::string_view path, int err) {
  const bool absent =
      err == ENOENT || err == ENODEV || err == ENXIO || err == EIO || err == EBUSY || err == EAGAIN;
  return Error::make(absent ? ErrorCode::kTransportUnavailable : ErrorCode::kTransport,
                     "%.*s %.*s: %s", static_cast<int>(what.size()), what.data(),
                     static_cast<int>(path.size()), path.data(), std::strerror(err));
}

Error io_error(std::string_view what, std::string_view name, int err) {
  return Error::make(
      is_disconnect_errno(err) ? ErrorCode::kTransportDisconnected : ErrorCode::kTransport,
      "%.*s on %.*s: %s", static_cast<int>(what.size()), what.data(), static_cast<int>(name.size()),
      name.data(), std::strerror(err));
}

Result<short> poll_with_wake(int fd, short events, int wake_fd, int timeout_ms) {
  pollfd fds[2] = {{fd, events, 0}, {wake_fd, POLLIN, 0}};
  const int n = ::poll(fds, wake_fd >= 0 ? 2 : 1, timeout_ms);
  if (n < 0) {
    if (errno == EINTR) return short{0};
    return Error::make(ErrorCode::kTransport, "poll: %s", std::strerror(errno));
  }
  if (wake_fd >= 0 && (fds[1].revents & POLLIN)) drain_wake_fd(wake_fd);
  return fds[0].revents;
}

}  // namespace tlvlink::transport::internal
