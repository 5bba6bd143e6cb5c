// The reconnect schedule the camera sources share, on a fake clock: the delay doubles up to its
// bound while reopening fails, restarts only after the device delivered frames, keeps growing
// when the device opens but fails again before its first frame, and the outage clock adds up.
#include "tlvlink/capture/reconnect_backoff.h"

#include <gtest/gtest.h>

#include <vector>

namespace tlvlink::capture {
namespace {

constexpr int64_t kNsPerMs = 1000000;

// Reopen attempts that all fail from `from_ns` on; the times they are made at, in ms from from_ns.
std::vector<int64_t> failing_attempts(ReconnectBackoff& b, int64_t from_ns, int64_t until_ns) {
  std::vector<int64_t> at;
  for (int64_t t = from_ns; t <= until_ns; t += kNsPerMs) {  // a caller polling every millisecond
    if (!b.due(t)) continue;
    at.push_back((t - from_ns) / kNsPerMs);
    b.attempt_failed(t);
  }
  return at;
}

TEST(ReconnectBackoff, DoublesUpToItsBoundWhileReopeningFails) {
  ReconnectBackoff b(100, 2000);
  b.lost(0, true);
  EXPECT_TRUE(b.in_outage());
  EXPECT_FALSE(b.due(99 * kNsPerMs));
  EXPECT_TRUE(b.due(100 * kNsPerMs));
  const std::vector<int64_t> expected = {100, 300, 700, 1500, 3100, 5100, 7100};
  EXPECT_EQ(failing_attempts(b, 0, 7500 * kNsPerMs), expected);
  EXPECT_EQ(b.delay_ms(), 2000);
}

TEST(ReconnectBackoff, RestartsAfterFramesFlowed) {
  ReconnectBackoff b(100, 2000);
  b.lost(0, true);
  failing_attempts(b, 0, 3100 * kNsPerMs);  // delay grown to 2000
  b.reopened(3100 * kNsPerMs);
  EXPECT_FALSE(b.in_outage());
  EXPECT_FALSE(b.due(3200 * kNsPerMs)) << "no attempts while connected";
  b.lost(10000 * kNsPerMs, /*streamed=*/true);
  EXPECT_EQ(b.delay_ms(), 100);
  EXPECT_EQ(b.next_attempt_ns(), 10100 * kNsPerMs);
}

// The HIL's "open succeeds, streaming fails" case: each reopen works, the device fails again
// before delivering a frame. Without memory the cycle would restart at 100 ms forever.
TEST(ReconnectBackoff, OpenThenFailBeforeAFrameKeepsGrowing) {
  ReconnectBackoff b(100, 2000);
  b.lost(0, true);
  int64_t t = 0;
  std::vector<int32_t> delays;
  for (int i = 0; i < 7; ++i) {
    t = b.next_attempt_ns();
    b.reopened(t);                // opened...
    b.lost(t + kNsPerMs, false);  // ...and lost again before the first frame
    delays.push_back(b.delay_ms());
  }
  const std::vector<int32_t> expected = {200, 400, 800, 1600, 2000, 2000, 2000};
  EXPECT_EQ(delays, expected);
}

TEST(ReconnectBackoff, FirstLossWithoutFramesStartsAtInitial) {
  ReconnectBackoff b(50, 400);
  b.lost(5 * kNsPerMs, false);  // the first open never delivered: nothing to grow from yet
  EXPECT_EQ(b.delay_ms(), 50);
  EXPECT_EQ(b.next_attempt_ns(), 55 * kNsPerMs);
}

TEST(ReconnectBackoff, AbsentAtStartTriesAtOnce) {
  ReconnectBackoff b(100, 2000);
  b.absent_at_start(7 * kNsPerMs);
  EXPECT_TRUE(b.due(7 * kNsPerMs));
  b.attempt_failed(7 * kNsPerMs);
  EXPECT_EQ(b.next_attempt_ns(), 207 * kNsPerMs);
}

TEST(ReconnectBackoff, OutageClockCountsEveryOutage) {
  ReconnectBackoff b(100, 2000);
  EXPECT_EQ(b.outage_ns(1000 * kNsPerMs), 0);
  b.lost(1000 * kNsPerMs, true);
  EXPECT_EQ(b.outage_ns(1250 * kNsPerMs), 250 * kNsPerMs);
  EXPECT_EQ(b.current_outage_ns(1250 * kNsPerMs), 250 * kNsPerMs);
  b.reopened(1400 * kNsPerMs);
  EXPECT_EQ(b.outage_ns(5000 * kNsPerMs), 400 * kNsPerMs);
  EXPECT_EQ(b.current_outage_ns(5000 * kNsPerMs), 0);
  b.lost(6000 * kNsPerMs, true);
  EXPECT_EQ(b.outage_ns(6100 * kNsPerMs), 500 * kNsPerMs);
  b.reset();
  EXPECT_FALSE(b.in_outage());
  EXPECT_EQ(b.outage_ns(9000 * kNsPerMs), 0);
}

TEST(ReconnectBackoff, DelayNeverExceedsItsBound) {
  ReconnectBackoff b(60000, 60000);  // the configurable extremes
  b.lost(0, true);
  for (int i = 0; i < 40; ++i) b.attempt_failed(0);
  EXPECT_EQ(b.delay_ms(), 60000);
  ReconnectBackoff c(10, 60000);
  c.lost(0, true);
  for (int i = 0; i < 40; ++i) c.lost(0, false);  // no int32 overflow
  EXPECT_EQ(c.delay_ms(), 60000);
}

}  // namespace
}  // namespace tlvlink::capture
