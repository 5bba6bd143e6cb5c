// Frame-level behaviour: determinism, the no-contact frame, LED extremes, and that a contact
// only changes the frame near the contact.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "sim/render/render_test_util.h"

namespace tlvlink::sim {
namespace {

using testing::diff_stats;
using testing::make_renderer;
using testing::quiet;
using testing::render_ok;
using testing::sphere;

TEST(SimRenderDeterminism, SameInputsGiveTheSameBytes) {
  auto a = make_renderer("gelsight-mini", 11);
  auto b = make_renderer("gelsight-mini", 11);
  ASSERT_TRUE(a && b);
  ContactScene s = sphere(4);
  s.texture.sq_um = 20;
  s.loading.shear_x_n = 1;
  RenderOptions o;
  o.markers = true;
  const Frame f1 = render_ok(*a, s, o, 99);
  const Frame f2 = render_ok(*a, s, o, 99);
  const Frame f3 = render_ok(*b, s, o, 99);  // another instance of the same sensor
  EXPECT_EQ(f1.rgb, f2.rgb);
  EXPECT_EQ(f1.rgb, f3.rgb);
  EXPECT_EQ(f1.state.force_n, f3.state.force_n);
  EXPECT_EQ(f1.state.press_mm, f3.state.press_mm);
  ASSERT_EQ(f1.markers.size(), f3.markers.size());
  for (size_t i = 0; i < f1.markers.size(); ++i) {
    EXPECT_EQ(f1.markers[i].x, f3.markers[i].x);
    EXPECT_EQ(f1.markers[i].y, f3.markers[i].y);
  }
}

TEST(SimRenderDeterminism, NoiseSeedAndSensorSeedMatter) {
  auto a = make_renderer("gelsight-mini", 11);
  auto b = make_renderer("gelsight-mini", 12);
  ASSERT_TRUE(a && b);
  const ContactScene s = sphere(4);
  const Frame f1 = render_ok(*a, s, RenderOptions{}, 1);
  const Frame f2 = render_ok(*a, s, RenderOptions{}, 2);
  EXPECT_NE(f1.rgb, f2.rgb);
  EXPECT_EQ(f1.state.force_n, f2.state.force_n);  // noise never changes the physics
  EXPECT_NE(a->background(), b->background());    // a seed is a physical sensor
}

TEST(SimRenderNoContact, FrameIsTheBackgroundPlusNoise) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  ContactScene s;
  s.geometry.shape = Shape::kNone;
  // Without noise the frame is the background exactly.
  const Frame clean = render_ok(*r, s, quiet());
  EXPECT_EQ(clean.rgb, r->background());
  EXPECT_FALSE(clean.state.in_contact);
  EXPECT_EQ(clean.state.force_n, 0);
  EXPECT_EQ(clean.state.contact_area_mm2, 0);
  // With the profile's noise (sigma 3 DN): the difference has zero mean and std sigma; rounding
  // both images adds at most 2 x 1/12 DN^2 of variance. 230k samples: sampling error ~0.2 %.
  const Frame noisy = render_ok(*r, s, RenderOptions{}, 5);
  const auto d = diff_stats(noisy.rgb, r->background());
  constexpr double kSigma = 3.0;
  constexpr double kMeanTolerance = 0.05;  // DN; ~7x the standard error of the mean
  EXPECT_NEAR(d.mean, 0.0, kMeanTolerance);
  EXPECT_GE(d.stddev, kSigma * 0.98);
  EXPECT_LE(d.stddev, std::sqrt(kSigma * kSigma + 2.0 / 12.0) * 1.02);
}

TEST(SimRenderNoContact, ZeroForceAndObjectOutOfViewDoNotTouch) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  const Frame zero = render_ok(*r, sphere(0), quiet());
  EXPECT_FALSE(zero.state.in_contact);
  EXPECT_EQ(zero.rgb, r->background());
  ContactScene far = sphere(5);
  far.geometry.center_x_mm = 500;
  const Frame away = render_ok(*r, far, quiet());
  EXPECT_FALSE(away.state.in_contact);
  EXPECT_EQ(away.rgb, r->background());
}

TEST(SimRenderFrameSize, EveryProfileRendersItsOwnSize) {
  for (std::string_view name : sensor_profile_names()) {
    SCOPED_TRACE(std::string(name));
    auto r = make_renderer(name);
    ASSERT_NE(r, nullptr);
    RenderOptions o;
    o.markers = true;
    const Frame f = render_ok(*r, sphere(3), o);
    EXPECT_EQ(f.height, r->profile().height);
    EXPECT_EQ(f.width, r->profile().width);
    EXPECT_EQ(f.rgb.size(), static_cast<size_t>(f.height) * static_cast<size_t>(f.width) * 3);
    EXPECT_EQ(f.markers.size(),
              static_cast<size_t>(r->profile().marker_rows * r->profile().marker_cols));
    EXPECT_TRUE(f.state.in_contact);
  }
}

TEST(SimRenderLeds, OffGivesABlackFrame) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  RenderOptions off;
  off.led_gain = 0;
  const Frame f = render_ok(*r, sphere(5), off);
  double sum = 0;
  for (uint8_t v : f.rgb) sum += v;
  // Only the clamped camera noise remains: E[max(0, 3 N(0,1))] = 3 / sqrt(2 pi) = 1.2 DN.
  constexpr double kMaxMeanDn = 2.0;
  EXPECT_LT(sum / static_cast<double>(f.rgb.size()), kMaxMeanDn);
}

TEST(SimRenderLeds, SaturationClampsWithoutWrapping) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  RenderOptions bright;
  bright.led_gain = 10;
  bright.markers = true;
  const Frame f = render_ok(*r, sphere(5), bright);
  const auto full = std::count(f.rgb.begin(), f.rgb.end(), uint8_t{255});
  EXPECT_GT(static_cast<double>(full), 0.9 * static_cast<double>(f.rgb.size()));
  // A wrapped overflow would show as dark pixels; only the marker dots may be darker.
  const auto dark = std::count_if(f.rgb.begin(), f.rgb.end(), [](uint8_t v) { return v < 100; });
  EXPECT_LT(static_cast<double>(dark), 0.02 * static_cast<double>(f.rgb.size()));
}

TEST(SimRenderLocality, AContactOnlyChangesTheFrameAroundIt) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  const Frame f = render_ok(*r, sphere(2, 3), quiet());
  ASSERT_TRUE(f.state.in_contact);
  const auto& bg = r->background();
  auto px = [&](const std::vector<uint8_t>& img, int x, int y, int c) {
    return img[(static_cast<size_t>(y) * 320 + static_cast<size_t>(x)) * 3 +
               static_cast<size_t>(c)];
  };
  // Far corner: untouched. Centre (inside the contact, on a slope): changed.
  for (int c = 0; c < 3; ++c) EXPECT_EQ(px(f.rgb, 5, 5, c), px(bg, 5, 5, c));
  int changed = 0;
  for (int y = 100; y < 140; ++y) {
    for (int x = 140; x < 180; ++x) {
      for (int c = 0; c < 3; ++c) changed += px(f.rgb, x, y, c) != px(bg, x, y, c);
    }
  }
  EXPECT_GT(changed, 1000);
}

}  // namespace
}  // namespace tlvlink::sim
