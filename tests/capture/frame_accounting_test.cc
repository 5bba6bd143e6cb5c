// Frame accounting: sequence normalisation and gaps (with 32-bit wrap), warm-up, bad frames,
// stale frames, and the frame rate from timestamps.
#include "tlvlink/capture/frame_accounting.h"

#include <gtest/gtest.h>

#include <vector>

namespace tlvlink::capture {
namespace {

using image::FrameFormat;
using image::PixelFormat;

constexpr int64_t kPeriod40ms = 40'000'000;  // a Mini at 25 fps

class Accounting : public ::testing::Test {
 protected:
  SourceStats stats;
  FrameAccounting acc{stats};
  FrameFormat grey{PixelFormat::kGrey, 8, 4, 0};
  std::vector<uint8_t> good = std::vector<uint8_t>(32, 7);

  Admission feed(uint32_t seq, int64_t t_ns, bool error = false, size_t bytes = 32) {
    return acc.admit(RawFrame{std::span(good).first(bytes), seq, t_ns, error}, grey);
  }
};

TEST_F(Accounting, FirstFrameIsSequenceZero) {
  acc.reset_stream(0);
  EXPECT_EQ(feed(1234, 1), Admission::kDeliverable);
  EXPECT_EQ(acc.sequence(), 0u);
  feed(1235, 2);
  EXPECT_EQ(acc.sequence(), 1u);
  EXPECT_EQ(stats.dropped, 0u);
}

TEST_F(Accounting, GapsAreDrops) {
  acc.reset_stream(0);
  feed(10, 1);
  feed(11, 2);
  feed(15, 3);  // 12, 13, 14 never reached us
  EXPECT_EQ(acc.sequence(), 5u);
  EXPECT_EQ(stats.dropped, 3u);
}

TEST_F(Accounting, WrapOfTheDriverCounterIsNotAGap) {
  acc.reset_stream(0);
  uint32_t seq = 0xFFFFFFFDu;
  for (int i = 0; i < 6; ++i) feed(seq++, i + 1);
  EXPECT_EQ(acc.sequence(), 5u);
  EXPECT_EQ(stats.dropped, 0u);
  EXPECT_EQ(stats.sequence_resets, 0u);
  feed(seq + 1, 10);  // one lost right after the wrap
  EXPECT_EQ(stats.dropped, 1u);
}

TEST_F(Accounting, BackwardsSequenceIsAResetNotAHugeGap) {
  acc.reset_stream(0);
  feed(500, 1);
  feed(501, 2);
  feed(3, 3);
  EXPECT_EQ(stats.sequence_resets, 1u);
  EXPECT_EQ(stats.dropped, 0u);
  EXPECT_EQ(acc.sequence(), 2u);
}

TEST_F(Accounting, ReopenRestartsAtZero) {
  acc.reset_stream(0);
  feed(77, 1);
  feed(78, 2);
  acc.reset_stream(0);
  feed(5, 3);
  EXPECT_EQ(acc.sequence(), 0u);
  EXPECT_EQ(stats.dropped, 0u);
}

TEST_F(Accounting, WarmupDiscardsGoodFramesOnly) {
  acc.reset_stream(2);
  EXPECT_EQ(feed(0, 1, /*error=*/true), Admission::kBad);  // a bad frame does not use up warm-up
  EXPECT_EQ(feed(1, 2), Admission::kWarmup);
  EXPECT_EQ(feed(2, 3), Admission::kWarmup);
  EXPECT_EQ(feed(3, 4), Admission::kDeliverable);
  EXPECT_EQ(stats.warmup_discarded, 2u);
  EXPECT_EQ(stats.flagged_error, 1u);
  acc.reset_stream(1);  // again after a reopen
  EXPECT_EQ(feed(0, 5), Admission::kWarmup);
  EXPECT_EQ(stats.warmup_discarded, 3u);
}

TEST_F(Accounting, BadFramesAreCountedByKind) {
  acc.reset_stream(0);
  feed(0, 1, true);
  feed(1, 2, false, 0);
  feed(2, 3, false, 31);
  EXPECT_EQ(stats.flagged_error, 1u);
  EXPECT_EQ(stats.empty, 1u);
  EXPECT_EQ(stats.short_frames, 1u);
  EXPECT_EQ(acc.problem(), FrameProblem::kShort);

  FrameFormat mjpeg{PixelFormat::kMjpeg, 3280, 2464, 0};
  const std::vector<uint8_t> torn = {0xFF, 0xD8, 0x01, 0x02};
  EXPECT_EQ(acc.admit(RawFrame{torn, 3, 4, false}, mjpeg), Admission::kBad);
  EXPECT_EQ(stats.bad_mjpeg, 1u);
  EXPECT_EQ(acc.problem(), FrameProblem::kNoEoi);
}

TEST_F(Accounting, FpsFromTimestamps) {
  acc.reset_stream(0);
  for (uint32_t i = 0; i < 40; ++i) feed(i, 1'000'000'000 + i * kPeriod40ms);
  EXPECT_NEAR(stats.measured_fps, 25.0, 1e-9);
  // A Mini on Linux: 18.75 fps (53.33 ms) even when 25 is nominal.
  acc.reset_stream(0);
  for (uint32_t i = 0; i < 40; ++i) feed(i, 5'000'000'000 + i * 53'333'333);
  EXPECT_NEAR(stats.measured_fps, 18.75, 1e-3);
}

TEST_F(Accounting, MissingTimestampsDoNotDistortFps) {
  acc.reset_stream(0);
  for (uint32_t i = 0; i < 20; ++i) feed(i, i % 5 == 4 ? 0 : 1'000'000'000 + i * kPeriod40ms);
  EXPECT_NEAR(stats.measured_fps, 25.0, 1e-9);
}

// The identity the V4L2 source relies on: every dequeued buffer is counted exactly once, and
// together with the gaps they account for every sequence number the driver issued.
TEST_F(Accounting, EveryFrameAccountedFor) {
  acc.reset_stream(3);
  uint32_t seq = 100;
  uint64_t issued = 0;
  for (int round = 0; round < 50; ++round) {
    // A "drain": 1-3 ready buffers, sometimes one bad, sometimes a gap before them.
    if (round % 7 == 3) {
      seq += 2;
      issued += 2;
    }
    const int ready = 1 + round % 3;
    int newest = -1;
    uint32_t stale = 0;
    for (int k = 0; k < ready; ++k) {
      const bool bad = (round + k) % 11 == 5;
      ++issued;
      if (feed(seq++, 1 + static_cast<int64_t>(issued) * kPeriod40ms, bad) ==
          Admission::kDeliverable) {
        if (newest >= 0) ++stale;
        newest = k;
      }
    }
    if (newest >= 0) {
      acc.count_stale(stale);
      acc.count_delivered();
    }
  }
  const uint64_t counted = stats.delivered + stats.skipped_stale + stats.warmup_discarded +
                           stats.flagged_error + stats.empty + stats.short_frames + stats.bad_mjpeg;
  EXPECT_EQ(counted + stats.dropped, issued);
  EXPECT_EQ(acc.sequence() + 1, issued);
}

}  // namespace
}  // namespace tlvlink::capture
