#pragma once
// The board clock: CLOCK_MONOTONIC in nanoseconds. Steady (it never jumps with the wall clock)
// and the clock of V4L2 buffer timestamps, so capture times, pipeline stages, stream timestamps,
// timeouts and pacing are all on one clock. Every read in runtime/ and firmware/ goes through
// board_clock_ns(); a test installs a FakeClock to move it by hand instead of sleeping.

#include <atomic>
#include <cstdint>

namespace tlvlink {

inline constexpr int64_t kNsPerMs = 1'000'000;
inline constexpr int64_t kNsPerS = 1'000'000'000;

int64_t board_clock_ns();

// Sleeps until the board clock reads `when_ns` (at once if it already does; early on a
// signal). Under a FakeClock it moves the fake time forward to `when_ns` and returns at once, so
// code that paces itself (a replay at the camera's rate) runs at test speed.
void sleep_until_ns(int64_t when_ns);

// The test hook: while a FakeClock exists, board_clock_ns() reads it. One at a time; make it
// before the code under test reads the clock and destroy it after any thread reading it stopped.
// Reads and moves are atomic (threads may read it while the test advances it).
class FakeClock {
 public:
  explicit FakeClock(int64_t start_ns = kNsPerS);
  ~FakeClock();
  FakeClock(const FakeClock&) = delete;
  FakeClock& operator=(const FakeClock&) = delete;

  int64_t now_ns() const { return now_.load(std::memory_order_acquire); }
  void advance_ns(int64_t ns) { now_.fetch_add(ns, std::memory_order_acq_rel); }
  void advance_ms(int64_t ms) { advance_ns(ms * kNsPerMs); }
  // Moves to `when_ns` if that is later (a clock never goes back).
  void advance_to(int64_t when_ns);

 private:
  std::atomic<int64_t> now_;
};

}  // namespace tlvlink
