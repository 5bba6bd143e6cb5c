// The board clock: steady on CLOCK_MONOTONIC, and the FakeClock tests move by hand.
#include "tlvlink/clock.h"

#include <ctime>
#include <thread>

#include <gtest/gtest.h>

namespace tlvlink {
namespace {

int64_t clock_monotonic_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * kNsPerS + ts.tv_nsec;
}

TEST(BoardClock, IsClockMonotonic) {
  const int64_t before = clock_monotonic_ns();
  const int64_t board = board_clock_ns();
  const int64_t after = clock_monotonic_ns();
  EXPECT_LE(before, board);
  EXPECT_LE(board, after);
}

TEST(BoardClock, SleepUntilAPastTimeReturnsAtOnce) {
  const int64_t t0 = board_clock_ns();
  sleep_until_ns(t0 - kNsPerS);
  EXPECT_LT(board_clock_ns() - t0, 100 * kNsPerMs);  // generous: a busy emulator
}

TEST(FakeClock, ReplacesTheBoardClockWhileItExists) {
  {
    FakeClock fake(5 * kNsPerS);
    EXPECT_EQ(board_clock_ns(), 5 * kNsPerS);
    fake.advance_ms(40);
    EXPECT_EQ(board_clock_ns(), 5 * kNsPerS + 40 * kNsPerMs);
    fake.advance_to(fake.now_ns() - 1);  // never back
    EXPECT_EQ(board_clock_ns(), 5 * kNsPerS + 40 * kNsPerMs);
  }
  EXPECT_GT(board_clock_ns(), 0);
  EXPECT_NE(board_clock_ns(), 5 * kNsPerS + 40 * kNsPerMs);
}

TEST(FakeClock, SleepUntilMovesItForwardWithoutWaiting) {
  FakeClock fake(kNsPerS);
  const int64_t real0 = clock_monotonic_ns();
  sleep_until_ns(kNsPerS + 3600 * kNsPerS);  // an hour of fake time
  EXPECT_EQ(board_clock_ns(), kNsPerS + 3600 * kNsPerS);
  EXPECT_LT(clock_monotonic_ns() - real0, kNsPerS);
  sleep_until_ns(0);  // in the past: no change
  EXPECT_EQ(board_clock_ns(), kNsPerS + 3600 * kNsPerS);
}

TEST(FakeClock, ThreadsSeeItAdvance) {
  FakeClock fake(0);
  int64_t seen = -1;
  std::thread reader([&] {
    while (board_clock_ns() < 10 * kNsPerMs) std::this_thread::yield();
    seen = board_clock_ns();
  });
  for (int i = 0; i < 10; ++i) fake.advance_ms(1);
  reader.join();
  EXPECT_EQ(seen, 10 * kNsPerMs);
}

}  // namespace
}  // namespace tlvlink
