// The grasp head's difference features (heads/grasp_difference.h) on images whose statistics are
// known in closed form. Tolerance 1e-4 on the log1p values: float sums over 36,864 values and
// the blur's float taps (normalised to sum 1 within ~1e-7).
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/heads/grasp_difference.h"
#include "tlvlink/heads/grasp_layout.h"

namespace tlvlink::heads {
namespace {

constexpr int32_t kH = 96, kW = 128;
constexpr size_t kValues = static_cast<size_t>(kH) * kW * 3;
constexpr double kTol = 1e-4;

float lg(double v) { return static_cast<float>(v < 0 ? -std::log1p(-v) : std::log1p(v)); }

std::vector<float> run(const std::vector<float>& before, const std::vector<float>& during) {
  auto g = GraspDifference::create(kH, kW, 3);
  EXPECT_TRUE(g.ok()) << g.error().message();
  std::vector<float> out(kDifferenceFeatures, -1.0f);
  const Status st = g->compute(before, during, out);
  EXPECT_TRUE(st.ok()) << st.error().message();
  return out;
}

TEST(GraspDifference, AnUnchangedImageGivesZeros) {
  std::vector<float> img(kValues);
  for (size_t i = 0; i < kValues; ++i) img[i] = static_cast<float>((i * 37) % 256);
  for (float v : run(img, img)) EXPECT_EQ(v, 0.0f);
}

TEST(GraspDifference, AUniformChangeGivesItsExactStatistics) {
  const std::vector<float> before(kValues, 100.0f), during(kValues, 110.0f);
  const std::vector<float> s = run(before, during);
  const float want[kDifferenceFeatures] = {
      lg(10), lg(100), lg(1),  lg(0), lg(0),  // raw: mean |d|, mean d^2, > 5.5 / 15.5 / 30.5
      lg(10), lg(1),   lg(1),  lg(0), lg(0),  // blurred: mean, > 3 / 8 / 15 / 30
      lg(10), lg(10),  lg(10),                // mean d per channel
      lg(10), lg(10),  lg(10)};               // mean b per channel (the blur keeps a constant)
  for (int k = 0; k < kDifferenceFeatures; ++k) EXPECT_NEAR(s[k], want[k], kTol) << "feature " << k;
}

TEST(GraspDifference, ALocalDarkeningKeepsItsCountItsSignAndItsChannel) {
  // The red channel 45 DN darker over a 10x10 block far from the borders.
  std::vector<float> before(kValues, 120.0f), during(kValues, 120.0f);
  for (int32_t y = 40; y < 50; ++y)
    for (int32_t x = 60; x < 70; ++x) during[(static_cast<size_t>(y) * kW + x) * 3] -= 45.0f;
  const std::vector<float> s = run(before, during);
  const double n = kValues, per_channel = n / 3;
  EXPECT_NEAR(s[0], lg(45.0 * 100 / n), kTol);
  EXPECT_NEAR(s[1], lg(45.0 * 45 * 100 / n), kTol);
  for (int k = 2; k <= 4; ++k) EXPECT_NEAR(s[k], lg(100 / n), kTol) << "raw fraction " << k;
  EXPECT_NEAR(s[10], lg(-45.0 * 100 / per_channel), kTol);  // signed: darker
  EXPECT_EQ(s[11], 0.0f);
  EXPECT_EQ(s[12], 0.0f);
  // The blur spreads the block but keeps its sum (normalised taps, all of d of one sign).
  EXPECT_NEAR(s[13], lg(45.0 * 100 / per_channel), kTol);
  EXPECT_EQ(s[14], 0.0f);
  EXPECT_GT(s[6], s[2]);  // more values over 3 DN blurred than over 5.5 DN raw
  EXPECT_LT(s[9], s[4]);  // fewer over 30 DN: the block's edges are smoothed
}

TEST(GraspDifference, TheBlurReflectsAtTheBordersAndKeepsAConstantOnTinyImages) {
  // One green value 45 DN darker at the corner (0, 0): with BORDER_REFLECT_101 only tap -x reads
  // source 0 at output x < 5 along each axis, so the blurred block sums 45 (g0 + ... + g4)^2,
  // g the normalised Gaussian taps (sigma 1.2, radius 4).
  std::vector<float> before(kValues, 120.0f), during(kValues, 120.0f);
  during[1] -= 45.0f;
  double g[5], total = 0;
  for (int i = -4; i <= 4; ++i) total += std::exp(-(i * i) / (2 * 1.2 * 1.2));
  double half = 0;
  for (int i = 0; i <= 4; ++i) half += g[i] = std::exp(-(i * i) / (2 * 1.2 * 1.2)) / total;
  const std::vector<float> s = run(before, during);
  const double per_channel = kValues / 3.0;
  EXPECT_NEAR(s[14], lg(45.0 * half * half / per_channel), kTol);  // |b| summed, green
  EXPECT_EQ(s[13], 0.0f);
  EXPECT_EQ(s[15], 0.0f);
  // Images smaller than the 9 taps reflect more than once; a uniform change stays uniform.
  for (const auto& [h, w] : {std::pair{2, 2}, std::pair{3, 5}, std::pair{7, 2}}) {
    auto small = GraspDifference::create(h, w, 3);
    ASSERT_TRUE(small.ok()) << small.error().message();
    const std::vector<float> b(small->values(), 50.0f), d(small->values(), 62.0f);
    std::vector<float> out(kDifferenceFeatures);
    ASSERT_TRUE(small->compute(b, d, out).ok());
    EXPECT_NEAR(out[5], lg(12), kTol) << h << "x" << w;  // mean |b|
    for (int c = 13; c < 16; ++c) EXPECT_NEAR(out[c], lg(12), kTol) << h << "x" << w;
  }
}

TEST(GraspDifference, WrongSizesNonFiniteValuesAndOtherInputsAreErrors) {
  EXPECT_EQ(GraspDifference::create(kH, kW, 1).error().code(), ErrorCode::kModelUnsupported);
  EXPECT_EQ(GraspDifference::create(1, kW, 3).error().code(), ErrorCode::kInvalidArgument);
  auto g = GraspDifference::create(kH, kW, 3);
  ASSERT_TRUE(g.ok());
  std::vector<float> a(kValues, 1.0f), b(kValues, 2.0f), out(kDifferenceFeatures);
  std::vector<float> short_image(kValues - 1, 1.0f), short_out(kDifferenceFeatures - 1);
  EXPECT_EQ(g->compute(short_image, b, out).error().code(), ErrorCode::kShapeMismatch);
  EXPECT_EQ(g->compute(a, b, short_out).error().code(), ErrorCode::kShapeMismatch);
  a[7] = std::numeric_limits<float>::quiet_NaN();
  const Status st = g->compute(a, b, out);
  ASSERT_EQ(st.error().code(), ErrorCode::kNonFiniteValue);
  const std::string msg = st.error().message();
  EXPECT_NE(msg.find("'before'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("value 7"), std::string::npos) << msg;
}

TEST(GraspDifference, TheInputSpecKeepsTheModelsCropAndResizeInDn) {
  const float mean[3] = {0.5f, 0.4f, 0.3f}, stdev[3] = {0.2f, 0.2f, 0.2f};
  InputSpec model;
  model.height = 96;
  model.width = 128;
  model.crop_x = 4;
  model.crop_w = 300;
  model.crop_h = 200;
  model.channel_order = ChannelOrder::kBGR;
  model.mean = mean;
  model.std = stdev;
  const InputSpec dn = difference_input_spec(model);
  EXPECT_EQ(dn.height, 96);
  EXPECT_EQ(dn.crop_x, 4);
  EXPECT_EQ(dn.crop_w, 300);
  EXPECT_EQ(dn.channel_order, ChannelOrder::kBGR);
  ASSERT_EQ(dn.mean.size(), 3u);
  ASSERT_EQ(dn.std.size(), 3u);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(dn.mean[c], 0.0f);
    EXPECT_EQ(255 * dn.std[c], 1.0f);  // (v / 255 - 0) / (1 / 255) = v
  }
}

TEST(GraspLayout, DifferenceTokensReadTheFingersBeforeAndDuringFrames) {
  auto l = parse_grasp_layout("A.before, A.during, A.difference, B.difference");
  ASSERT_TRUE(l.ok()) << l.error().message();
  ASSERT_EQ(l->size(), 4u);
  EXPECT_EQ((*l)[2].kind, FeatureKind::kDifference);
  EXPECT_EQ((*l)[3].finger, 1);
  EXPECT_EQ(feature_values((*l)[0], 128), 128);
  EXPECT_EQ(feature_values((*l)[2], 128), kDifferenceFeatures);
  EXPECT_TRUE(has_difference(*l));
  EXPECT_TRUE(reads_frame(*l, 1, Moment::kBefore));
  EXPECT_TRUE(reads_frame(*l, 1, Moment::kDuring));
  EXPECT_FALSE(reads_frame(*l, 1, Moment::kAfter));
  const auto twice = parse_grasp_layout("A.difference,A.difference");
  ASSERT_FALSE(twice.ok());
  EXPECT_NE(std::string(twice.error().message()).find("named twice"), std::string::npos);
  EXPECT_EQ(parse_grasp_layout("A.diff").error().code(), ErrorCode::kModelInvalidMetadata);
}

}  // namespace
}  // namespace tlvlink::heads
