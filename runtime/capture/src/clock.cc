#include "clock.h"

#include <ctime>

namespace tlvlink::capture::internal {

int64_t monotonic_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * kNsPerS + ts.tv_nsec;
}

void sleep_until_ns(int64_t when_ns) {
  timespec ts{};
  ts.tv_sec = when_ns / kNsPerS;
  ts.tv_nsec = when_ns % kNsPerS;
  ::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
}

}  // namespace tlvlink::capture::internal
