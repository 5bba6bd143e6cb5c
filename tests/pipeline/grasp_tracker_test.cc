// The grasp tracker's phases in both modes on scripted frame streams: which frames it takes, the
// reasons a grasp is not computed, and that it never invents a value.
#include <array>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/pipeline/grasp_tracker.h"

namespace tlvlink::pipeline {
namespace {

using heads::GraspFeature;
using heads::Moment;

constexpr int64_t kMs = 1'000'000;
constexpr int32_t kDim = 4;
constexpr int64_t kPeriod = 40 * kMs;  // a Mini: 25 fps

const std::vector<GraspFeature> kLayout = {
    {0, Moment::kBefore}, {0, Moment::kDuring}, {1, Moment::kBefore}, {1, Moment::kDuring}};

// The embedding of finger f's frame k: recognisable values.
std::vector<float> emb(int32_t f, uint64_t k) {
  return std::vector<float>(kDim, static_cast<float>(f * 1000 + static_cast<int64_t>(k)));
}

struct Stream {
  GraspTracker tracker;
  std::vector<GraspPrediction> done;
  std::vector<std::vector<float>> features;  // of the last computed grasp, layout order
  int encoded[2] = {0, 0};

  // Both fingers' frame k at k * period (finger B 7 ms later), in contact when `contact(k)`.
  // Every frame is encoded, or only those the tracker wants.
  template <typename Contact>
  void run(uint64_t from, uint64_t to, Contact contact, int64_t b_offset = 7 * kMs,
           bool encode_only_when_wanted = false) {
    for (uint64_t k = from; k < to; ++k) {
      for (int32_t f = 0; f < 2; ++f) {
        const int64_t t = static_cast<int64_t>(k) * kPeriod + (f == 1 ? b_offset : 0);
        const bool c = contact(f, k);
        const bool encode = encode_only_when_wanted ? tracker.wants(f, t) : true;
        encoded[f] += encode ? 1 : 0;
        const std::vector<float> e = emb(f, k);
        tracker.on_frame(f, k, t, c, encode ? std::span<const float>(e) : std::span<const float>());
        drain();
      }
    }
  }
  void drain() {
    GraspPrediction p;
    std::span<const float> f[kMaxGraspFeatures];
    while (tracker.take_finished(p, f)) {
      done.push_back(p);
      if (p.computed) {
        features.clear();
        for (int32_t i = 0; i < p.frame_count; ++i)
          features.emplace_back(f[i].begin(), f[i].end());
      }
    }
  }
};

Stream make(GraspOptions o = {}) {
  auto t = GraspTracker::create(kLayout, kDim, o);
  EXPECT_TRUE(t.ok()) << t.error().message();
  return Stream{std::move(t).value(), {}, {}, {0, 0}};
}

const auto kAlways = [](int32_t, uint64_t) { return true; };

TEST(GraspTracker, DetectedGraspTakesTheOpenGelBeforeAndTheSettledGripDuring) {
  Stream s = make();
  // Contact on both fingers from frame 10 to 60 (0.4 s .. 2.4 s).
  s.run(0, 80, [](int32_t, uint64_t k) { return k >= 10 && k < 60; });
  ASSERT_EQ(s.done.size(), 1u);
  const GraspPrediction& p = s.done[0];
  EXPECT_TRUE(p.computed) << p.reason.data();
  EXPECT_EQ(p.grasp_id, 1u);
  // Start = the later onset (B at 400 + 7 ms). before = each finger's last open-gel frame: 9
  // (360 / 367 ms). during = first frames >= 407 + 300 ms: A frame 18 (720), B frame 18 (727).
  EXPECT_EQ(p.started_ns, 407 * kMs);
  ASSERT_EQ(p.frame_count, 4);
  EXPECT_EQ(p.frames[0].sequence, 9u);
  EXPECT_EQ(p.frames[1].sequence, 18u);
  EXPECT_EQ(p.frames[2].sequence, 9u);
  EXPECT_EQ(p.frames[3].sequence, 18u);
  EXPECT_EQ(p.frames[3].capture_ns, 18 * kPeriod + 7 * kMs);
  ASSERT_EQ(s.features.size(), 4u);
  EXPECT_EQ(s.features[0], emb(0, 9));
  EXPECT_EQ(s.features[1], emb(0, 18));
  EXPECT_EQ(s.features[3], emb(1, 18));
  EXPECT_EQ(s.tracker.grasps_started(), 1u);
  // The prediction exists before the lift could have started: at the "during" frame.
  EXPECT_EQ(p.decided_ns, 18 * kPeriod + 7 * kMs);
}

TEST(GraspTracker, OneFingerOrSkewedOnsetsAreNotAGrasp) {
  Stream s = make();
  s.run(0, 60, [](int32_t f, uint64_t k) { return f == 0 && k >= 5; });  // a press by A alone
  s.run(60, 120, [](int32_t f, uint64_t k) { return f == 0 || k >= 100; });  // B 1.6 s later
  EXPECT_TRUE(s.done.empty());
  EXPECT_EQ(s.tracker.grasps_started(), 0u);
}

TEST(GraspTracker, ReasonsAGraspIsNotComputed) {
  {  // finger B lets go before its "during" frame
    Stream s = make();
    s.run(0, 80, [](int32_t f, uint64_t k) { return k >= 10 && (f == 0 || k < 15); });
    ASSERT_EQ(s.done.size(), 1u);
    EXPECT_FALSE(s.done[0].computed);
    EXPECT_STREQ(s.done[0].reason.data(), "finger B let go before its 'during' frame");
  }
  {  // B's camera drops frames 18 and 19: its first 'during' frame is 87 ms after A's
    Stream s = make();
    for (uint64_t k = 0; k < 80; ++k) {
      for (int32_t f = 0; f < 2; ++f) {
        if (f == 1 && (k == 18 || k == 19)) continue;
        const int64_t t = static_cast<int64_t>(k) * kPeriod + (f == 1 ? 7 * kMs : 0);
        const std::vector<float> e = emb(f, k);
        s.tracker.on_frame(f, k, t, k >= 10, e);
        s.drain();
      }
    }
    ASSERT_EQ(s.done.size(), 1u);
    EXPECT_FALSE(s.done[0].computed);
    EXPECT_STREQ(s.done[0].reason.data(),
                 "the fingers' 'during' frames are 87.0 ms apart (tolerance 50.0 ms)");
  }
  {  // B's camera goes silent after frame 15: timed out by tick()
    Stream s = make();
    s.run(0, 16, [](int32_t, uint64_t k) { return k >= 10; });
    for (uint64_t k = 16; k < 80; ++k) {
      const std::vector<float> e = emb(0, k);
      s.tracker.on_frame(0, k, static_cast<int64_t>(k) * kPeriod, true, e);
      s.tracker.tick(static_cast<int64_t>(k) * kPeriod);
      s.drain();
    }
    ASSERT_EQ(s.done.size(), 1u);
    EXPECT_STREQ(s.done[0].reason.data(), "finger B sent no frame within 500 ms of its 'during' moment");
  }
  {  // the caller did not encode a frame the tracker wanted
    Stream s = make();
    for (uint64_t k = 0; k < 40; ++k) {
      for (int32_t f = 0; f < 2; ++f) {
        const std::vector<float> e = emb(f, k);
        const bool skip = f == 1 && k == 18;
        s.tracker.on_frame(f, k, static_cast<int64_t>(k) * kPeriod + (f == 1 ? 7 * kMs : 0),
                           k >= 10, skip ? std::span<const float>() : std::span<const float>(e));
        s.drain();
      }
    }
    ASSERT_EQ(s.done.size(), 1u);
    EXPECT_STREQ(s.done[0].reason.data(), "finger B frame 18 (its 'during' frame) was not encoded");
  }
  {  // the fingers touch from their first frame: no open gel was ever seen
    Stream s = make();
    s.run(0, 40, kAlways);
    ASSERT_EQ(s.done.size(), 1u);
    EXPECT_STREQ(s.done[0].reason.data(),
                 "finger A has no frame of its open gel before the grasp (its 'before' moment)");
  }
  {  // the only open-gel frames encoded are too old to stand for "before"
    GraspOptions o;
    o.idle_refresh_ns = 100 * kMs;
    o.before_max_age_ns = 200 * kMs;
    Stream s = make(o);
    for (uint64_t k = 0; k < 40; ++k) {
      for (int32_t f = 0; f < 2; ++f) {
        const std::vector<float> e = emb(f, k);
        const bool encode = k == 0 || k >= 10;
        s.tracker.on_frame(f, k, static_cast<int64_t>(k) * kPeriod + (f == 1 ? 7 * kMs : 0),
                           k >= 10, encode ? std::span<const float>(e) : std::span<const float>());
        s.drain();
      }
    }
    ASSERT_EQ(s.done.size(), 1u);
    EXPECT_STREQ(s.done[0].reason.data(),
                 "finger A's last open-gel frame is 0.4 s old (before_max_age 0.2 s)");
  }
}

TEST(GraspTracker, WantsMakesTheCallerEncodeExactlyTheFramesTaken) {
  Stream s = make();
  s.run(0, 80, [](int32_t, uint64_t k) { return k >= 10 && k < 60; }, 7 * kMs, true);
  ASSERT_EQ(s.done.size(), 1u);
  EXPECT_TRUE(s.done[0].computed) << s.done[0].reason.data();
  // Per finger: the open gel at frame 0 (refreshed every 500 ms: none due before contact at
  // 400 ms), "during" at 18, and after both let go (frame 60) the open gel again at 61 and 74.
  EXPECT_EQ(s.done[0].frames[0].sequence, 0u);
  EXPECT_EQ(s.encoded[0], 4);
  EXPECT_EQ(s.encoded[1], 4);
}

TEST(GraspTracker, CommandedModeUsesTheControllersMarks) {
  GraspOptions o;
  o.mode = GraspOptions::Mode::kCommanded;
  o.settle_ns = 100 * kMs;
  Stream s = make(o);
  s.run(0, 5, [](int32_t, uint64_t) { return false; });
  EXPECT_TRUE(s.tracker.mark_closed(210 * kMs));  // before: the open gel of frame 4
  EXPECT_TRUE(s.tracker.mark_lifting(260 * kMs));  // the lift comes before the grip settled
  s.run(5, 12, kAlways);
  ASSERT_EQ(s.done.size(), 1u);
  ASSERT_TRUE(s.done[0].computed) << s.done[0].reason.data();
  EXPECT_EQ(s.done[0].frames[0].sequence, 4u);
  EXPECT_EQ(s.done[0].frames[1].sequence, 7u);  // during: at the lift (280 ms), not 310 ms
  // A new "closed" before the grip settled supersedes the grasp in progress.
  EXPECT_TRUE(s.tracker.mark_closed(1300 * kMs));
  s.run(30, 33, kAlways);
  EXPECT_TRUE(s.tracker.mark_closed(1330 * kMs));
  s.drain();
  ASSERT_EQ(s.done.size(), 2u);
  EXPECT_STREQ(s.done[1].reason.data(), "superseded by a new 'closed' mark");
  EXPECT_EQ(s.done[1].grasp_id, 2u);
  // Marks mean nothing in detected mode.
  Stream d = make();
  EXPECT_FALSE(d.tracker.mark_closed(0));
  EXPECT_FALSE(d.tracker.mark_lifting(0));
}

TEST(GraspTracker, BadOptionsAndLayoutsAreErrors) {
  GraspOptions o;
  o.settle_ns = -1;
  EXPECT_NE(std::string(GraspTracker::create(kLayout, kDim, o).error().message()).find("grasp.settle_ms"),
            std::string::npos);
  const std::vector<GraspFeature> seven(7, GraspFeature{0, Moment::kBefore});
  EXPECT_EQ(GraspTracker::create(seven, kDim, {}).error().code(), ErrorCode::kModelUnsupported);
}

}  // namespace
}  // namespace tlvlink::pipeline
