#pragma once
// Counts heap allocations made through the global operator new family while counting is on,
// for the no-allocation tests of frame-loop code (STYLE.md: setup allocates, the frame loop does
// not). Linking tests/support/alloc_counter.cc (target tlvlink_alloc_counter) replaces every
// global operator new / delete of the test binary; link it into no-allocation tests only.

#include <cstddef>

namespace tlvlink::testing {

void start_counting_allocations();   // resets the count
size_t stop_counting_allocations();  // the allocations since start

}  // namespace tlvlink::testing
