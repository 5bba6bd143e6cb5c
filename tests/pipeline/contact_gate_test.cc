// Contact gating on synthetic gel frames: calibration, onset on a small imprint, hysteresis on
// release, drift following while idle, re-zero, errors, and no allocation per frame.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "support/alloc_counter.h"
#include "support/random.h"
#include "tlvlink/pipeline/contact_gate.h"

namespace tlvlink::pipeline {
namespace {

constexpr int32_t kW = 320, kH = 240;
constexpr float kNoiseDn = 2.0f;  // camera noise sigma of the synthetic frames

// A lit gel (smooth gradient) with noise, optionally a round imprint of `depth_dn` at (cx, cy).
std::vector<uint8_t> gel(testing::Rng& rng, float offset = 0, float depth_dn = 0, int cx = 160,
                         int cy = 120, int radius = 12) {
  std::vector<uint8_t> px(static_cast<size_t>(kW * kH * 3));
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float d2 = static_cast<float>((x - cx) * (x - cx) + (y - cy) * (y - cy));
      const float imprint = d2 < static_cast<float>(radius * radius) ? depth_dn : 0.0f;
      for (int c = 0; c < 3; ++c) {
        const float v = 100.0f + 0.2f * static_cast<float>(x) + 30.0f * static_cast<float>(c) +
                        offset + imprint + rng.normal(0, kNoiseDn);
        px[static_cast<size_t>((y * kW + x) * 3 + c)] =
            static_cast<uint8_t>(std::clamp(v, 0.0f, 255.0f));
      }
    }
  return px;
}

image::ImageView view(const std::vector<uint8_t>& px) { return {px.data(), kW, kH, 3, 0}; }

ContactGate calibrated(testing::Rng& rng, const ContactGateOptions& o = {}) {
  auto g = ContactGate::create(kW, kH, 3, o);
  EXPECT_TRUE(g.ok());
  for (int i = 0; i < o.reference_frames; ++i) {
    auto d = g->update(view(gel(rng)));
    EXPECT_TRUE(d.ok());
    if (i + 1 < o.reference_frames) {
      EXPECT_EQ(d->state, ContactState::kCalibrating);
    }
  }
  EXPECT_EQ(g->state(), ContactState::kNoContact);
  return std::move(g).value();
}

TEST(ContactGate, CalibratesOnNoiseAndSeesASmallImprint) {
  testing::Rng rng(1);
  ContactGate g = calibrated(rng);
  // Block means of 10x10 pixels: noise sigma ~ 2 / 10 = 0.2 DN (plus the 8-bit rounding).
  EXPECT_GT(g.noise_sigma_dn(), 0.05f);
  EXPECT_LT(g.noise_sigma_dn(), 0.5f);
  EXPECT_FLOAT_EQ(g.threshold_dn(), std::max(4.0f, 8 * g.noise_sigma_dn()));
  for (int i = 0; i < 50; ++i) {
    auto d = g.update(view(gel(rng)));
    ASSERT_TRUE(d.ok());
    EXPECT_EQ(d->state, ContactState::kNoContact) << "false contact on noise, frame " << i;
  }
  // A 12-px (0.8 mm on a Mini) imprint 10 DN deep starts contact on its first frame.
  auto d = g.update(view(gel(rng, 0, 10)));
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->state, ContactState::kContact);
  EXPECT_TRUE(d->onset);
}

// The mask marks the cells the imprint covers: a 30 DN imprint of radius 12 px at (160, 120) on
// the default 32x24 grid of 10x10-px cells covers cells 14..17 x 10..13 (its edge cells partly).
TEST(ContactGate, TheMaskMarksTheImprintsCells) {
  testing::Rng rng(5);
  auto fresh = ContactGate::create(kW, kH, 3, {});
  ASSERT_TRUE(fresh.ok());
  std::vector<uint8_t> bits(32 * 24 / 8, 0xFF);
  ASSERT_TRUE(fresh->update(view(gel(rng, 0, 30))).ok());
  ASSERT_TRUE(fresh->contact_mask(bits).ok());
  for (uint8_t b : bits) EXPECT_EQ(b, 0) << "calibrating: no cell is marked";
  ContactGate g = calibrated(rng);
  ASSERT_TRUE(g.update(view(gel(rng, 0, 30))).value().onset);
  ASSERT_TRUE(g.contact_mask(bits).ok());
  const auto cell = [&](int x, int y) {
    return ((bits[static_cast<size_t>((y * 32 + x) / 8)] >> ((y * 32 + x) % 8)) & 1) != 0;
  };
  EXPECT_TRUE(cell(15, 11) && cell(16, 11) && cell(15, 12) && cell(16, 12))
      << "the imprint's centre cells";
  int marked = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      marked += cell(x, y) ? 1 : 0;
      if (x < 14 || x > 17 || y < 10 || y > 13) {
        EXPECT_FALSE(cell(x, y)) << x << "," << y;
      }
    }
  EXPECT_LE(marked, 16);
  std::vector<uint8_t> wrong(95);
  EXPECT_EQ(g.contact_mask(wrong).error().code(), ErrorCode::kInvalidArgument);
  testing::start_counting_allocations();
  const Status st = g.contact_mask(bits);
  EXPECT_EQ(testing::stop_counting_allocations(), 0u);
  EXPECT_TRUE(st.ok());
}

TEST(ContactGate, ReleaseNeedsConsecutiveQuietFramesAndDriftIsFollowedOnlyWhileIdle) {
  testing::Rng rng(2);
  ContactGateOptions o;
  o.release_frames = 3;
  ContactGate g = calibrated(rng, o);
  ASSERT_TRUE(g.update(view(gel(rng, 0, 30))).value().onset);
  // Two quiet frames, a touch again, then three quiet frames: released on the last.
  EXPECT_EQ(g.update(view(gel(rng))).value().state, ContactState::kContact);
  EXPECT_EQ(g.update(view(gel(rng))).value().state, ContactState::kContact);
  EXPECT_EQ(g.update(view(gel(rng, 0, 30))).value().state, ContactState::kContact);
  for (int i = 0; i < 2; ++i)
    EXPECT_EQ(g.update(view(gel(rng))).value().state, ContactState::kContact);
  auto released = g.update(view(gel(rng)));
  EXPECT_TRUE(released->release);
  EXPECT_EQ(released->state, ContactState::kNoContact);
  // Slow drift (0.05 DN per frame, 6 DN in all) is followed: no contact.
  for (int i = 1; i <= 120; ++i) {
    auto d = g.update(view(gel(rng, 0.05f * static_cast<float>(i))));
    ASSERT_EQ(d->state, ContactState::kNoContact)
        << "drift frame " << i << " score " << d->score_dn;
  }
  // A step of the same size is contact.
  EXPECT_EQ(g.update(view(gel(rng, 6.0f + 12.0f))).value().state, ContactState::kContact);
}

// The frame that completes the reference is judged like the next ones: a press that began while
// the gate calibrated (frames dropped under load can put one there) is contact at once, and the
// frame's mask, which marks where it differs from the reference, never marks a no-contact frame.
TEST(ContactGate, TheFrameThatCompletesTheReferenceIsJudgedToo) {
  testing::Rng rng(5);
  ContactGateOptions o;
  auto quiet = ContactGate::create(kW, kH, 3, o);
  ASSERT_TRUE(quiet.ok());
  for (int i = 0; i + 1 < o.reference_frames; ++i) (void)quiet->update(view(gel(rng)));
  auto last = quiet->update(view(gel(rng)));
  ASSERT_TRUE(last.ok());
  EXPECT_EQ(last->state, ContactState::kNoContact) << "score " << last->score_dn;
  EXPECT_GT(last->score_dn, 0.0f) << "the completing frame is scored";
  EXPECT_LT(last->score_dn, last->threshold_dn);

  auto pressed = ContactGate::create(kW, kH, 3, o);
  ASSERT_TRUE(pressed.ok());
  for (int i = 0; i + 1 < o.reference_frames; ++i) (void)pressed->update(view(gel(rng)));
  auto d = pressed->update(view(gel(rng, 0, 40)));  // the press begins on the last reference frame
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->state, ContactState::kContact);
  EXPECT_TRUE(d->onset);
  std::vector<uint8_t> mask((static_cast<size_t>(o.grid_width * o.grid_height) + 7) / 8);
  ASSERT_TRUE(pressed->contact_mask(mask).ok());
  int marked = 0;
  for (uint8_t b : mask) marked += __builtin_popcount(b);
  EXPECT_GT(marked, 0) << "the frame in contact marks its cells";
}

TEST(ContactGate, RezeroRecalibratesAndErrorsNameTheProblem) {
  testing::Rng rng(3);
  ContactGate g = calibrated(rng);
  g.rezero();
  EXPECT_EQ(g.update(view(gel(rng, 40))).value().state, ContactState::kCalibrating);
  std::vector<uint8_t> small(10 * 10 * 3);
  auto bad = g.update({small.data(), 10, 10, 3, 0});
  ASSERT_FALSE(bad.ok());
  EXPECT_STREQ(bad.error().message(), "contact gate: frame 10x10x3, expected 320x240x3");
  ContactGateOptions o;
  o.reference_frames = 0;
  EXPECT_EQ(ContactGate::create(kW, kH, 3, o).error().code(), ErrorCode::kInvalidArgument);
  o = {};
  o.drift_rate = 1;
  EXPECT_NE(std::string(ContactGate::create(kW, kH, 3, o).error().message()).find("drift_rate"),
            std::string::npos);
}

TEST(ContactGate, UpdateAllocatesNothing) {
  testing::Rng rng(4);
  ContactGate g = calibrated(rng);
  const auto a = gel(rng), b = gel(rng, 0, 30);
  testing::start_counting_allocations();
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(g.update(view(i % 2 ? a : b)).ok());
  EXPECT_EQ(testing::stop_counting_allocations(), 0u);
}

}  // namespace
}  // namespace tlvlink::pipeline
