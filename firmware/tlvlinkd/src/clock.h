#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "clock.h is internal to firmware/tlvlinkd"
#endif
// Per-thread CPU time. The board clock itself is core's (tlvlink/clock.h: board_clock_ns).

#include <pthread.h>
#include <time.h>

#include <cstdint>

#include "tlvlink/clock.h"

namespace tlvlink::daemon::internal {

// The calling thread's CPU clock, for another thread to read (thread_cpu_ns).
inline clockid_t this_thread_cpu_clock() {
  clockid_t id = CLOCK_THREAD_CPUTIME_ID;
  pthread_getcpuclockid(pthread_self(), &id);
  return id;
}

inline int64_t thread_cpu_ns(clockid_t clock) {
  timespec ts{};
  if (clock_gettime(clock, &ts) != 0) return 0;
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace tlvlink::daemon::internal
