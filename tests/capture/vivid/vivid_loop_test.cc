// Our own frames through a real capture node: vivid's output->capture loop. Looped frames arrive
// bit-exact; a consumer slower or faster than the feed sees gaps and duplicates (as with a real
// sensor); the extreme frames (all 0, all 255, noise) pass untouched and are not flagged as bad;
// a feed that stops does not look like a stopped camera in vivid (it repeats the last frame).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <thread>
#include <vector>

#include "tlvlink/capture/v4l2_source.h"
#include "vivid/loop_feeder.h"
#include "vivid/vivid_support.h"

namespace tlvlink::capture {
namespace {

using vivid::Pattern;

class VividLoop : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto reason = vivid::absent_reason(); !reason.empty()) GTEST_SKIP() << reason;
    nodes = *vivid::find_nodes();
    if (nodes.output.empty())
      GTEST_SKIP() << "vivid has no output node (load it with node_types=0x101)";
  }

  // Output first (vivid loops only from a streaming output), then the capture source.
  void open(Pattern pattern) {
    auto f = vivid::LoopFeeder::start(nodes, image::PixelFormat::kYuyv, pattern);
    ASSERT_TRUE(f.ok()) << f.error().message();
    feeder = std::move(*f);
    auto cfg = vivid::capture_config(nodes, image::PixelFormat::kYuyv, vivid::kLoopWidth,
                                     vivid::kLoopHeight, 0);
    cfg.controls = parse_controls("osd_text_mode=2, loop_video=1").value();
    auto s = make_v4l2_source(cfg);
    ASSERT_TRUE(s.ok());
    src = std::move(*s);
    Status st = src->start();
    ASSERT_TRUE(st.ok()) << st.error().message();
  }

  // The frame's index, after checking every byte against what was fed with that index.
  bool identify(const CapturedFrame& f, Pattern pattern, uint32_t& index) {
    if (!vivid::frame_index(f.bytes, index)) return false;
    expected.resize(f.bytes.size());
    vivid::frame_pattern(pattern, index, expected);
    return std::equal(expected.begin(), expected.end(), f.bytes.begin());
  }

  void TearDown() override {
    src.reset();
    feeder.reset();
  }

  vivid::Nodes nodes;
  std::unique_ptr<vivid::LoopFeeder> feeder;
  std::unique_ptr<V4l2Source> src;
  std::vector<uint8_t> expected;
};

// Counts what a consumer reading every `read_ms` sees of a feed changing every `feed_ms`.
struct Seen {
  int frames = 0, exact = 0, duplicates = 0, gaps = 0, not_looped = 0;
  // Duplicates although the feeder had queued two frames or more since the previous read: a stale
  // frame delivered. The others are the feeder's thread not running (a loaded guest).
  int duplicates_while_fed = 0;
};

TEST_F(VividLoop, FramesArriveBitExactWithDuplicatesAndGaps) {
  open(Pattern::kIndexed);
  ASSERT_FALSE(HasFatalFailure());
  auto watch = [&](int feed_ms, int read_ms, int frames) {
    Seen s;
    feeder->feed_every(feed_ms);
    uint32_t last = 0, queued_before = feeder->frames_queued();
    bool have_last = false;
    for (int i = 0; i < frames; ++i) {
      auto f = src->next(3000);
      const uint32_t queued = feeder->frames_queued();
      EXPECT_TRUE(f.ok()) << f.error().message();
      if (!f.ok()) break;
      uint32_t index = 0;
      ++s.frames;
      if (!identify(*f, Pattern::kIndexed, index)) {
        ++s.not_looped;  // vivid's own pattern (the feed had not started): not ours
      } else {
        ++s.exact;
        if (have_last && index == last) {
          ++s.duplicates;
          if (queued - queued_before >= 2) ++s.duplicates_while_fed;
        }
        if (have_last && index > last + 1) s.gaps += static_cast<int>(index - last - 1);
        last = index;
        have_last = true;
      }
      queued_before = queued;
      src->release();
      if (read_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(read_ms));
    }
    return s;
  };
  // Fed at 10 fps, read at ~60 fps: each fed frame is captured several times.
  const Seen slow_feed = watch(100, 0, 40);
  // Fed at ~30 fps, read at ~7 fps: the newest frame wins, the ones in between are gaps.
  const Seen slow_reader = watch(33, 150, 10);
  std::printf(
      "note: feed 10 fps / read 60 fps: %d frames, %d bit-exact, %d duplicates, %d gaps, %d not "
      "looped\n",
      slow_feed.frames, slow_feed.exact, slow_feed.duplicates, slow_feed.gaps,
      slow_feed.not_looped);
  std::printf(
      "note: feed 30 fps / read 7 fps: %d frames, %d bit-exact, %d duplicates (%d while fed), %d "
      "gaps\n",
      slow_reader.frames, slow_reader.exact, slow_reader.duplicates,
      slow_reader.duplicates_while_fed, slow_reader.gaps);
  EXPECT_GE(slow_feed.exact, 30);
  EXPECT_LE(slow_feed.not_looped, 3);
  EXPECT_GE(slow_feed.duplicates, 15);
  EXPECT_EQ(slow_reader.exact, slow_reader.frames);
  EXPECT_GE(slow_reader.gaps, 10);
  // Beside the other test stages (2026-12-05) the guest's feeder thread once stalled for a read
  // period: 2 duplicates. A duplicate counts against the source only if frames were fed.
  EXPECT_LE(slow_reader.duplicates_while_fed, 1);
  std::printf("note: source: %llu delivered, %llu stale skipped, %llu dropped, measured %.1f fps\n",
              static_cast<unsigned long long>(src->stats().delivered),
              static_cast<unsigned long long>(src->stats().skipped_stale),
              static_cast<unsigned long long>(src->stats().dropped), src->stats().measured_fps);
}

TEST_F(VividLoop, ExtremeFramesPassUntouched) {
  for (Pattern p : {Pattern::kAllZero, Pattern::kAllMax, Pattern::kNoise}) {
    SCOPED_TRACE(static_cast<int>(p));
    open(p);
    ASSERT_FALSE(HasFatalFailure());
    feeder->feed_every(50);
    int exact = 0;
    for (int i = 0; i < 8; ++i) {
      auto f = src->next(3000);
      ASSERT_TRUE(f.ok()) << f.error().message();
      uint32_t index = 0;
      if (identify(*f, p, index)) ++exact;
      src->release();
    }
    const SourceStats& s = src->stats();
    EXPECT_GE(exact, 6);
    EXPECT_EQ(s.flagged_error + s.empty + s.short_frames + s.bad_mjpeg, 0u);
    src.reset();
    feeder.reset();
  }
}

TEST_F(VividLoop, StoppedFeedRepeatsTheLastFrame) {
  open(Pattern::kIndexed);
  ASSERT_FALSE(HasFatalFailure());
  feeder->feed_every(40);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  feeder->feed_every(0);  // the feed stops; the output keeps its last buffer
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const uint32_t last_fed = feeder->frames_queued() - 1;
  // Frames fed before the last may still be in flight (the loop's latency grows with the
  // emulated board's load): wait for the last one, then it must be all there is.
  int before_last = 0;
  for (bool reached = false; !reached; ++before_last) {
    ASSERT_LT(before_last, 25) << "the last fed frame (" << last_fed << ") never arrived";
    auto f = src->next(500);
    ASSERT_TRUE(f.ok()) << "vivid keeps capturing when the feed stops: " << f.error().message();
    uint32_t index = 0;
    reached = identify(*f, Pattern::kIndexed, index) && index == last_fed;
    src->release();
  }
  int repeats = 1;
  for (int i = 1; i < 10; ++i) {
    auto f = src->next(500);
    ASSERT_TRUE(f.ok()) << "vivid keeps capturing when the feed stops: " << f.error().message();
    uint32_t index = 0;
    if (identify(*f, Pattern::kIndexed, index) && index == last_fed) ++repeats;
    src->release();
  }
  EXPECT_EQ(repeats, 10) << before_last - 1 << " earlier frame(s) came first";
  // With the output stopped, the capture shows vivid's own test pattern: still no timeout.
  feeder->stop_output();
  int own_pattern = 0;
  for (int i = 0; i < 5; ++i) {
    auto f = src->next(500);
    ASSERT_TRUE(f.ok()) << f.error().message();
    uint32_t index = 0;
    if (!identify(*f, Pattern::kIndexed, index)) ++own_pattern;
    src->release();
  }
  EXPECT_GE(own_pattern, 4);
  EXPECT_EQ(src->stats().timeouts, 0u);
  std::printf(
      "note: feed stopped: the last fed frame repeated %d/10 times; output stopped: vivid's "
      "pattern "
      "%d/5; timeouts %llu (vivid cannot starve a capture this way: percentage_of_dropped_buffers "
      "does)\n",
      repeats, own_pattern, static_cast<unsigned long long>(src->stats().timeouts));
}

}  // namespace
}  // namespace tlvlink::capture
