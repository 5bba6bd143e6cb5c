// The no-contact background through the public API (Renderer::background(): before noise):
// vignetting 1 - k r^2 (r = 1 at a corner) darkens the corners, and the illumination
// polynomial makes the background non-uniform by up to, and about, the profile's amplitude.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "sim/render/render_test_util.h"

namespace tlvlink::sim {
namespace {

// Background value of channel c at pixel (x, y).
double at(const Renderer& r, int32_t x, int32_t y, int c) {
  const SensorProfile& p = r.profile();
  return r.background()[(static_cast<size_t>(y) * static_cast<size_t>(p.width) +
                         static_cast<size_t>(x)) *
                            3 +
                        static_cast<size_t>(c)];
}

// r^2 of pixel (x, y): 1 at the frame's corner (pixel centres stop half a pixel short).
double radius2(const SensorProfile& p, int32_t x, int32_t y) {
  const double dx = x + 0.5 - 0.5 * p.width, dy = y + 0.5 - 0.5 * p.height;
  return (dx * dx + dy * dy) / (0.25 * (p.width * p.width + p.height * p.height));
}

std::unique_ptr<Renderer> make(const SensorProfile& p, uint64_t seed) {
  auto r = Renderer::create(p, seed);
  EXPECT_TRUE(r.ok()) << r.error().message();
  return r.ok() ? std::move(r.value()) : nullptr;
}

constexpr uint64_t kSeeds = 10;  // sensor instances per profile

// With the polynomial off, corner / centre is 1 - k r^2 exactly but for the rounding to 8 bits,
// and the fall-off is monotone along the diagonal.
TEST(SimRenderBackground, VignettingFollowsOneMinusKRSquared) {
  // Rounding both pixels by <= 0.5 DN moves the ratio by <= (0.5 + 0.5 ratio) / centre <= 1 /
  // centre, and the centre is >= 100 DN here (b 120-130 DN, gain 0.92-1.08).
  constexpr double kRoundingTolerance = 1.0 / 100;
  for (double k : {0.1, 0.25, 0.5, 0.9}) {
    SensorProfile p = sensor_profile("gelsight-mini").value();
    p.background_nonuniformity_dn = 0;
    p.vignetting = k;
    auto r = make(p, 3);
    ASSERT_NE(r, nullptr);
    const int32_t w = p.width, h = p.height;
    for (int c = 0; c < 3; ++c) {
      const double centre = at(*r, w / 2, h / 2, c);
      for (auto [x, y] : {std::pair{0, 0}, {w - 1, 0}, {0, h - 1}, {w - 1, h - 1}}) {
        const double want = (1 - k * radius2(p, x, y)) / (1 - k * radius2(p, w / 2, h / 2));
        EXPECT_NEAR(at(*r, x, y, c) / centre, want, kRoundingTolerance) << k << " " << c;
      }
      for (int32_t i = 1; i < h / 2; ++i) {  // from a corner toward the centre: never darker
        const int32_t x = i * w / h, y = i;
        EXPECT_GE(at(*r, x, y, c), at(*r, x - w / h, y - 1, c)) << k << " " << i;
      }
    }
  }
}

// Every built-in profile, ten sensor instances each: the mean of the four corners is darker than
// the centre in every channel. It must be: corners are at most (1 - k)(b + a) and the centre is
// b (times the same gain), and every profile has k > a / (b + a).
TEST(SimRenderBackground, VignettingDarkensTheCornersOfEveryProfile) {
  for (std::string_view name : sensor_profile_names()) {
    SCOPED_TRACE(std::string(name));
    const SensorProfile p = sensor_profile(name).value();
    for (double b : p.background_rgb) {
      ASSERT_GT(p.vignetting, p.background_nonuniformity_dn / (b + p.background_nonuniformity_dn));
    }
    for (uint64_t seed = 1; seed <= kSeeds; ++seed) {
      auto r = make(p, seed);
      ASSERT_NE(r, nullptr);
      const int32_t w = p.width, h = p.height;
      for (int c = 0; c < 3; ++c) {
        const double corners = (at(*r, 0, 0, c) + at(*r, w - 1, 0, c) + at(*r, 0, h - 1, c) +
                                at(*r, w - 1, h - 1, c)) /
                               4;
        EXPECT_LT(corners, at(*r, w / 2, h / 2, c)) << "seed " << seed << " channel " << c;
      }
    }
  }
}

// The background divided by the vignetting is b_c + a poly_c (times the sensor's channel gain):
// |a poly_c| <= a everywhere, and it reaches a (the polynomial is normalised to max |poly| = 1
// over the frame): non-uniform by the stated amplitude, no more. The gain is read off the
// centre pixel, where poly and r are ~0. Measured max |a poly| - a over 4 profiles x 10 sensors
// x 3 channels: -0.16 .. +1.24 DN.
TEST(SimRenderBackground, NonUniformityStaysWithinTheStatedAmplitude) {
  // Rounding of the pixel: 0.5 DN / (gain x vignetting >= 0.92 x 0.70) = 0.78 DN; of the centre
  // pixel the gain comes from: 0.5 DN x b / centre <= 0.55 DN; the centre's own poly and the
  // camera blur of the polynomial: < 0.1 DN.
  constexpr double kToleranceDn = 1.5;
  for (std::string_view name : sensor_profile_names()) {
    SCOPED_TRACE(std::string(name));
    const SensorProfile p = sensor_profile(name).value();
    const double a = p.background_nonuniformity_dn;
    for (uint64_t seed = 1; seed <= kSeeds; ++seed) {
      auto r = make(p, seed);
      ASSERT_NE(r, nullptr);
      for (int c = 0; c < 3; ++c) {
        const double b = p.background_rgb[static_cast<size_t>(c)];
        const double gain = at(*r, p.width / 2, p.height / 2, c) /
                            (b * (1 - p.vignetting * radius2(p, p.width / 2, p.height / 2)));
        double worst = 0;
        for (int32_t y = 0; y < p.height; ++y) {
          for (int32_t x = 0; x < p.width; ++x) {
            const double illumination =
                at(*r, x, y, c) / (gain * (1 - p.vignetting * radius2(p, x, y)));
            worst = std::max(worst, std::fabs(illumination - b));
          }
        }
        EXPECT_LE(worst, a + kToleranceDn) << "seed " << seed << " channel " << c;
        EXPECT_GE(worst, a - kToleranceDn) << "seed " << seed << " channel " << c;
      }
    }
  }
  // Amplitude 0 and no vignetting: every pixel of a channel is the same.
  SensorProfile flat = sensor_profile("gelsight-mini").value();
  flat.background_nonuniformity_dn = 0;
  flat.vignetting = 0;
  auto r = make(flat, 1);
  ASSERT_NE(r, nullptr);
  for (int c = 0; c < 3; ++c) {
    for (int32_t y = 0; y < flat.height; y += 7) {
      for (int32_t x = 0; x < flat.width; x += 7) ASSERT_EQ(at(*r, x, y, c), at(*r, 0, 0, c));
    }
  }
}

}  // namespace
}  // namespace tlvlink::sim
