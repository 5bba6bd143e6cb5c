#include <sys/ioctl.h>

#include <cerrno>
#include <ctime>

#include "v4l2_internal.h"

namespace tlvlink::capture::internal {

int64_t monotonic_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

void sleep_until_ns(int64_t when_ns) {
  timespec ts{};
  ts.tv_sec = when_ns / 1000000000;
  ts.tv_nsec = when_ns % 1000000000;
  ::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
}

int xioctl(int fd, unsigned long request, void* arg) {
  int rc;
  do rc = ::ioctl(fd, request, arg);
  while (rc < 0 && errno == EINTR);
  return rc < 0 ? errno : 0;
}

}  // namespace tlvlink::capture::internal
