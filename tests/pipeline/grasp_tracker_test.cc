// The grasp tracker's phases in both modes on scripted frame streams: which frames it takes, the
// reasons a grasp is not computed, and that it never invents a value.
#include <array>
#include <cmath>
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
        for (int32_t i = 0; i < p.frame_count; ++i) features.emplace_back(f[i].begin(), f[i].end());
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
  s.run(0, 60, [](int32_t f, uint64_t k) { return f == 0 && k >= 5; });      // a press by A alone
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
    EXPECT_STREQ(s.done[0].reason.data(),
                 "finger B sent no frame within 500 ms of its 'during' moment");
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
  s.run(
      0, 80, [](int32_t, uint64_t k) { return k >= 10 && k < 60; }, 7 * kMs, true);
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
  EXPECT_TRUE(s.tracker.mark_closed(210 * kMs));   // before: the open gel of frame 4
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

// Two cameras' clocks are not the controller's: finger B's frames carry times 150 ms later than
// A's of the same moment, so when the "closed" mark arrives B's newest open-gel frame may be
// timestamped after it. Its previous one is then B's "before" (a live replay lost a grasp so).
TEST(GraspTracker, CommandedBeforeSurvivesAFingerClockAheadOfTheMark) {
  GraspOptions o;
  o.mode = GraspOptions::Mode::kCommanded;
  o.settle_ns = 100 * kMs;
  constexpr int64_t kAhead = 150 * kMs;
  {
    Stream s = make(o);
    // Open gels, encoded as the daemon does (what wants() asks for: every 500 ms): A at frames 0
    // (0 ms) and 13 (520), B at 0 (150) and 13 (670).
    s.run(
        0, 14, [](int32_t, uint64_t) { return false; }, kAhead, true);
    EXPECT_TRUE(s.tracker.mark_closed(560 * kMs));
    s.run(14, 24, kAlways, kAhead, true);
    ASSERT_EQ(s.done.size(), 1u);
    ASSERT_TRUE(s.done[0].computed) << s.done[0].reason.data();
    EXPECT_EQ(s.done[0].frames[0].sequence, 13u);  // A: its newest, before the mark
    EXPECT_EQ(s.done[0].frames[2].sequence, 0u);   // B: 670 ms is after the mark; 150 ms is not
    EXPECT_EQ(s.done[0].frames[2].capture_ns, kAhead);
    ASSERT_EQ(s.features.size(), 4u);
    EXPECT_EQ(s.features[2], emb(1, 0));
  }
  {  // B's only open-gel frame is later than the mark: it still shows the open gel
    Stream s = make(o);
    s.run(
        0, 1, [](int32_t, uint64_t) { return false; }, kAhead);
    EXPECT_TRUE(s.tracker.mark_closed(100 * kMs));
    s.run(1, 10, kAlways, kAhead);
    ASSERT_EQ(s.done.size(), 1u);
    ASSERT_TRUE(s.done[0].computed) << s.done[0].reason.data();
    EXPECT_EQ(s.done[0].frames[2].sequence, 0u);
    EXPECT_EQ(s.done[0].frames[2].capture_ns, kAhead);
  }
}

TEST(GraspTracker, BadOptionsAndLayoutsAreErrors) {
  GraspOptions o;
  o.settle_ns = -1;
  EXPECT_NE(
      std::string(GraspTracker::create(kLayout, kDim, o).error().message()).find("grasp.settle_ms"),
      std::string::npos);
  const std::vector<GraspFeature> nine(kMaxGraspFeatures + 1, GraspFeature{0, Moment::kBefore});
  EXPECT_EQ(GraspTracker::create(nine, kDim, {}).error().code(), ErrorCode::kModelUnsupported);
  // A difference feature needs images the statistics can read.
  const std::vector<GraspFeature> diff = {{0, Moment::kDuring, heads::FeatureKind::kDifference}};
  EXPECT_EQ(GraspTracker::create(diff, kDim, {}).error().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(GraspTracker::create(diff, kDim, {}, {8, 8, 1}).error().code(),
            ErrorCode::kModelUnsupported);
}

// Difference layouts: each finger's open-gel and settled-grip images, passed beside the
// embeddings, become the finger's 16 statistics. Finger f's frame k is a uniform image of
// f * 100 + k DN, so the difference is the frames' sequence gap.
const std::vector<GraspFeature> kDifferenceLayout = {
    {0, Moment::kBefore},
    {0, Moment::kDuring},
    {0, Moment::kDuring, heads::FeatureKind::kDifference},
    {1, Moment::kBefore},
    {1, Moment::kDuring},
    {1, Moment::kDuring, heads::FeatureKind::kDifference}};
constexpr GraspImageShape kImage{8, 8, 3};

struct DifferenceRun {
  std::vector<GraspPrediction> done;
  std::vector<std::vector<float>> features;  // of the last computed grasp
};

// Contact on both fingers from frame 10 to 60; images passed when `with_image(f, contact)`.
template <typename WithImage>
DifferenceRun run_difference(WithImage with_image) {
  auto t = GraspTracker::create(kDifferenceLayout, kDim, {}, kImage);
  EXPECT_TRUE(t.ok()) << t.error().message();
  DifferenceRun r;
  for (uint64_t k = 0; k < 80; ++k) {
    for (int32_t f = 0; f < 2; ++f) {
      const int64_t t_ns = static_cast<int64_t>(k) * kPeriod + (f == 1 ? 7 * kMs : 0);
      const bool contact = k >= 10 && k < 60;
      EXPECT_TRUE(t->wants_image(f));
      const std::vector<float> e = emb(f, k);
      const std::vector<float> image(t->image_values(), static_cast<float>(f * 100) + k);
      t->on_frame(
          f, k, t_ns, contact, e,
          with_image(f, contact) ? std::span<const float>(image) : std::span<const float>());
      GraspPrediction p;
      std::span<const float> feats[kMaxGraspFeatures];
      while (t->take_finished(p, feats)) {
        r.done.push_back(p);
        if (!p.computed) continue;
        r.features.clear();
        for (int32_t i = 0; i < p.feature_count; ++i)
          r.features.emplace_back(feats[i].begin(), feats[i].end());
      }
    }
  }
  return r;
}

TEST(GraspTracker, DifferenceFeaturesAreTheStatisticsOfEachFingersBeforeAndDuringImages) {
  const DifferenceRun r = run_difference([](int32_t, bool) { return true; });
  ASSERT_EQ(r.done.size(), 1u);
  const GraspPrediction& p = r.done[0];
  ASSERT_TRUE(p.computed) << p.reason.data();
  EXPECT_EQ(p.feature_count, 6);
  ASSERT_EQ(p.frame_count, 4);  // each frame once: A before, A during, B before, B during
  ASSERT_EQ(r.features.size(), 6u);
  for (int32_t k : {0, 1, 3, 4})
    EXPECT_EQ(r.features[static_cast<size_t>(k)].size(), static_cast<size_t>(kDim));
  for (int32_t finger : {0, 1}) {
    const GraspFrameRef& before = p.frames[static_cast<size_t>(finger * 2)];
    const GraspFrameRef& during = p.frames[static_cast<size_t>(finger * 2 + 1)];
    ASSERT_EQ(before.moment, static_cast<uint8_t>(Moment::kBefore));
    ASSERT_EQ(during.moment, static_cast<uint8_t>(Moment::kDuring));
    const double gap = static_cast<double>(during.sequence - before.sequence);
    EXPECT_GT(gap, 0);
    const std::vector<float>& d = r.features[static_cast<size_t>(finger * 3 + 2)];
    ASSERT_EQ(d.size(), static_cast<size_t>(heads::kDifferenceFeatures));
    EXPECT_NEAR(d[0], std::log1p(gap), 1e-5) << "finger " << finger;   // mean |d|
    EXPECT_NEAR(d[10], std::log1p(gap), 1e-5) << "finger " << finger;  // mean d, channel 0
    // The embeddings beside it are the same frames'.
    EXPECT_EQ(r.features[static_cast<size_t>(finger * 3)], emb(finger, before.sequence));
    EXPECT_EQ(r.features[static_cast<size_t>(finger * 3 + 1)], emb(finger, during.sequence));
  }
}

TEST(GraspTracker, DifferenceWithoutItsImagesIsNotComputedAndSaysWhy) {
  // Finger B's open-gel frames come without images: B has no "before" to compare against.
  DifferenceRun r = run_difference([](int32_t f, bool) { return f == 0; });
  ASSERT_EQ(r.done.size(), 1u);
  EXPECT_FALSE(r.done[0].computed);
  EXPECT_NE(std::string(r.done[0].reason.data()).find("finger B has no frame of its open gel"),
            std::string::npos)
      << r.done[0].reason.data();
  // B's grip frames come without images: its "during" cannot be compared.
  r = run_difference([](int32_t f, bool contact) { return f == 0 || !contact; });
  ASSERT_EQ(r.done.size(), 1u);
  EXPECT_FALSE(r.done[0].computed);
  EXPECT_NE(std::string(r.done[0].reason.data()).find("without the image"), std::string::npos)
      << r.done[0].reason.data();
}

}  // namespace
}  // namespace tlvlink::pipeline
