#pragma once
// The board clock every stream timestamp uses is core's board_clock_ns() (tlvlink/clock.h:
// CLOCK_MONOTONIC, the clock of V4L2 buffer timestamps, with a fake for tests). This name stays
// for the host tools that read it for receive times (hosts use their own CLOCK_MONOTONIC).

#include <cstdint>

#include "tlvlink/clock.h"

namespace tlvlink::transport {

inline int64_t monotonic_ns() { return board_clock_ns(); }

}  // namespace tlvlink::transport
