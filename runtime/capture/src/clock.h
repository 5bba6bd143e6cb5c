#pragma once
// CLOCK_MONOTONIC helpers shared by the sources of runtime/capture. Private to runtime/capture.
#ifndef TLVLINK_CAPTURE_PRIVATE
#error "runtime/capture internal header"
#endif

#include <cstdint>

namespace tlvlink::capture::internal {

inline constexpr int64_t kNsPerMs = 1000000;
inline constexpr int64_t kNsPerS = 1000000000;

int64_t monotonic_ns();
void sleep_until_ns(int64_t when_ns);  // CLOCK_MONOTONIC; returns early on a signal

}  // namespace tlvlink::capture::internal
