// Vision images: every class draws, any size, deterministic, with the class's colour and a
// visible pattern; bad sizes and views are errors.

#include <gtest/gtest.h>

#include <cmath>

#include "support/random.h"
#include "tlvlink/sim/vision.h"

namespace tlvlink::sim {
namespace {

struct Stats {
  double mean[3] = {0, 0, 0};
  double sd = 0;  // of the luminance
};

Stats stats(const RgbImage& im) {
  Stats s;
  const size_t n = static_cast<size_t>(im.height) * static_cast<size_t>(im.width);
  double lum = 0, lum2 = 0;
  for (size_t i = 0; i < n; ++i) {
    double l = 0;
    for (size_t c = 0; c < 3; ++c) {
      s.mean[c] += im.rgb[i * 3 + c];
      l += im.rgb[i * 3 + c] / 3.0;
    }
    lum += l;
    lum2 += l * l;
  }
  for (double& m : s.mean) m /= static_cast<double>(n);
  const double mu = lum / static_cast<double>(n);
  s.sd = std::sqrt(std::max(0.0, lum2 / static_cast<double>(n) - mu * mu));
  return s;
}

TEST(Vision, EveryClassRendersWithItsColourAndAPattern) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  VisionView flat;
  flat.noise_sigma_dn = 0;
  flat.light_strength = 0;
  for (const MaterialClass& c : material_classes()) {
    SCOPED_TRACE(std::string(c.name));
    MaterialSample m = sample_material(c.id, seed).value();
    RgbImage im;
    ASSERT_TRUE(render_vision_image(m, seed, flat, 0, 96, 128, im).ok());
    ASSERT_EQ(im.rgb.size(), 96u * 128u * 3u);
    const Stats s = stats(im);
    // The pattern shows (even glossy/plain surfaces vary by a few DN); not a flat fill.
    EXPECT_GT(s.sd, 1.5);
    // The image keeps the object's dominant channel (colour jitter aside).
    size_t top = 0;
    for (size_t k = 1; k < 3; ++k) top = m.colour[k] > m.colour[top] ? k : top;
    const double spread = m.colour[top] - std::min({m.colour[0], m.colour[1], m.colour[2]});
    if (spread > 30 && c.pattern != "patches") {  // patches mix in a second colour
      for (size_t k = 0; k < 3; ++k) {
        if (k != top) {
          EXPECT_GT(s.mean[top] + 5, s.mean[k]);
        }
      }
    }
  }
}

TEST(Vision, DeterministicAndSeeded) {
  const MaterialSample m = sample_material(3, 5).value();
  const VisionView view = random_vision_view(11);
  RgbImage a, b, c, d;
  ASSERT_TRUE(render_vision_image(m, 1, view, 2, 60, 80, a).ok());
  ASSERT_TRUE(render_vision_image(m, 1, view, 2, 60, 80, b).ok());
  ASSERT_TRUE(render_vision_image(m, 9, view, 2, 60, 80, c).ok());  // another object
  ASSERT_TRUE(render_vision_image(m, 1, view, 3, 60, 80, d).ok());  // other camera noise
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_NE(a.rgb, c.rgb);
  EXPECT_NE(a.rgb, d.rgb);
}

TEST(Vision, AnySize) {
  const MaterialSample m = sample_material(8, 5).value();
  RgbImage im;
  for (auto [h, w] : {std::pair{1, 1}, std::pair{7, 1000}, std::pair{480, 640}}) {
    ASSERT_TRUE(render_vision_image(m, 1, VisionView{}, 1, h, w, im).ok());
    EXPECT_EQ(im.height, h);
    EXPECT_EQ(im.width, w);
    EXPECT_EQ(im.rgb.size(), static_cast<size_t>(h) * static_cast<size_t>(w) * 3);
  }
}

TEST(Vision, BadArgumentsAreErrors) {
  const MaterialSample m = sample_material(0, 5).value();
  RgbImage im;
  EXPECT_EQ(render_vision_image(m, 1, VisionView{}, 1, 0, 10, im).error().code(),
            ErrorCode::kInvalidArgument);
  EXPECT_EQ(render_vision_image(m, 1, VisionView{}, 1, 10, 9000, im).error().code(),
            ErrorCode::kInvalidArgument);
  VisionView bad;
  bad.zoom = std::nan("");
  const Status s = render_vision_image(m, 1, bad, 1, 10, 10, im);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(std::string(s.error().message()).find("zoom"), std::string::npos);
  MaterialSample unknown = m;
  unknown.class_id = 99;
  EXPECT_FALSE(render_vision_image(unknown, 1, VisionView{}, 1, 10, 10, im).ok());
}

}  // namespace
}  // namespace tlvlink::sim
