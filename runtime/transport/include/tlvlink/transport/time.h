#pragma once
// The board clock every stream timestamp uses: CLOCK_MONOTONIC in nanoseconds (the clock of
// V4L2 buffer timestamps). Hosts use their own CLOCK_MONOTONIC for receive times.

#include <cstdint>
#include <ctime>

namespace tlvlink::transport {

inline int64_t monotonic_ns() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace tlvlink::transport
