// The plan/run preprocessing against the staged code the shipped models were trained through
// (staged_reference.cc): every filter, crop, channel order, 1- and 3-channel frames, shrinking
// and enlarging, must give the same float bits. Plus int8 encoding, errors, and no allocation.
#include <algorithm>
#include <array>
#include <cstring>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "image/staged_reference.h"
#include "support/alloc_counter.h"
#include "support/random.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::image {
namespace {

struct OwnedSpec {
  std::vector<float> mean, stdev;
  InputSpec spec;
};

OwnedSpec random_spec(testing::Rng& rng, int32_t frame_w, int32_t frame_h) {
  OwnedSpec o;
  InputSpec& s = o.spec;
  s.channel_order = static_cast<ChannelOrder>(rng.int_in(0, 2));
  s.channels = s.channel_order == ChannelOrder::kGray ? 1 : 3;
  s.resize_filter = static_cast<ResizeFilter>(rng.int_in(0, 2));
  s.height = rng.int_in(1, 2 * frame_h);
  s.width = rng.int_in(1, 2 * frame_w);
  if (rng.coin()) {
    s.crop_w = rng.int_in(1, frame_w);
    s.crop_h = rng.int_in(1, frame_h);
    s.crop_x = rng.int_in(0, frame_w - s.crop_w);
    s.crop_y = rng.int_in(0, frame_h - s.crop_h);
  }
  for (int32_t c = 0; c < s.channels; ++c) {
    o.mean.push_back(rng.uniform(0.0f, 1.0f));
    o.stdev.push_back(rng.uniform(0.05f, 1.0f));
  }
  s.mean = o.mean;
  s.std = o.stdev;
  return o;
}

// An RGB spec into height x width by `filter`, with these per-channel means and stds.
OwnedSpec rgb_spec(int32_t height, int32_t width, ResizeFilter filter, std::vector<float> mean,
                   std::vector<float> stdev) {
  OwnedSpec o;
  o.mean = std::move(mean);
  o.stdev = std::move(stdev);
  o.spec.height = height;
  o.spec.width = width;
  o.spec.resize_filter = filter;
  o.spec.mean = o.mean;
  o.spec.std = o.stdev;
  return o;
}

Image random_image(testing::Rng& rng, int32_t w, int32_t h, int32_t channels) {
  Image img{w, h, channels, {}};
  img.pixels.resize(static_cast<size_t>(w * h * channels));
  for (uint8_t& p : img.pixels) p = static_cast<uint8_t>(rng.int_in(0, 255));
  return img;
}

TEST(ImagePreprocessPlan, BitIdenticalToTheStagedPreprocessing) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  for (int trial = 0; trial < 400; ++trial) {
    const int32_t w = rng.int_in(1, 48), h = rng.int_in(1, 48);
    const Image frame = random_image(rng, w, h, rng.coin() ? 3 : 1);
    OwnedSpec o = random_spec(rng, w, h);
    auto want = testing::staged::preprocess(frame, o.spec);
    ASSERT_TRUE(want.ok()) << want.error().message();
    auto plan = PreprocessPlan::create(o.spec, w, h, frame.channels);
    ASSERT_TRUE(plan.ok()) << plan.error().message();
    std::vector<float> got(plan->output_values());
    ASSERT_TRUE(plan->run(frame.view(), std::span<float>(got)).ok());
    ASSERT_EQ(got.size(), want->size());
    // Bit for bit, not within a tolerance: the shipped models were trained on these values.
    ASSERT_EQ(std::memcmp(got.data(), want->data(), got.size() * sizeof(float)), 0)
        << "trial " << trial << ": " << w << "x" << h << "x" << frame.channels << " -> "
        << o.spec.width << "x" << o.spec.height << " filter "
        << static_cast<int>(o.spec.resize_filter) << " crop " << o.spec.crop_w;
  }
}

TEST(ImagePreprocessPlan, TheDeploymentSizesAreBitIdenticalToo) {
  // The shipped models' path: a 320x240 processed frame (and a 240x320 DIGIT one, cropped) into
  // 128x96 RGB by area (what the models record), and bilinear.
  testing::Rng rng(7);
  for (const ResizeFilter filter : {ResizeFilter::kArea, ResizeFilter::kBilinear}) {
    for (const auto& [w, h, crop_h] : {std::tuple{320, 240, 0}, std::tuple{240, 320, 180}}) {
      const Image frame = random_image(rng, w, h, 3);
      OwnedSpec o = rgb_spec(96, 128, filter, {0.41f, 0.45f, 0.52f}, {0.19f, 0.18f, 0.21f});
      if (crop_h > 0) {  // a centred band, as a sensor view crops
        o.spec.crop_y = 70;
        o.spec.crop_w = w;
        o.spec.crop_h = crop_h;
      }
      auto want = testing::staged::preprocess(frame, o.spec);
      auto got = preprocess(frame, o.spec);
      ASSERT_TRUE(want.ok() && got.ok());
      EXPECT_EQ(std::memcmp(got->data(), want->data(), got->size() * sizeof(float)), 0)
          << w << "x" << h << " filter " << static_cast<int>(filter);
    }
  }
  const Image frame = random_image(rng, 320, 240, 3);
  EXPECT_EQ(resize_bilinear(frame, 96, 128).pixels,
            testing::staged::resize_bilinear(frame, 96, 128).pixels);
}

TEST(ImagePreprocessPlan, AreaMeansOfLargeBoxesAreExactToo) {
  // Boxes of 4,095, 4,096 and 6,000 pixels (sums past 2^20) against the staged division.
  testing::Rng rng(11);
  for (const auto& [w, h] : {std::pair{63, 65}, std::pair{64, 64}, std::pair{100, 60}}) {
    for (uint8_t fill : {uint8_t{0}, uint8_t{255}, uint8_t{1}}) {
      Image frame = random_image(rng, w, h, 3);
      if (fill != 1) std::fill(frame.pixels.begin(), frame.pixels.end(), fill);
      const OwnedSpec o =
          rgb_spec(1, 1, ResizeFilter::kArea, {0.5f, 0.5f, 0.5f}, {0.25f, 0.25f, 0.25f});
      auto want = testing::staged::preprocess(frame, o.spec);
      auto got = preprocess(frame, o.spec);
      ASSERT_TRUE(want.ok() && got.ok());
      EXPECT_EQ(std::memcmp(got->data(), want->data(), got->size() * sizeof(float)), 0)
          << w << "x" << h << " fill " << int{fill};
    }
  }
}

TEST(ImagePreprocessPlan, ResizeIsRunsFirstStage) {
  // The trainer resizes augmented frames through resize(): run() must be exactly those pixels,
  // normalised, for every filter.
  testing::Rng rng(23);
  for (ResizeFilter filter :
       {ResizeFilter::kBilinear, ResizeFilter::kArea, ResizeFilter::kNearest}) {
    for (const auto& [w, h, ow, oh] :
         {std::array<int32_t, 4>{320, 240, 128, 96}, std::array<int32_t, 4>{37, 29, 11, 7},
          std::array<int32_t, 4>{12, 10, 30, 20}}) {
      const Image frame = random_image(rng, w, h, 3);
      OwnedSpec o;
      o.mean = {0.41f, 0.45f, 0.52f};
      o.stdev = {0.19f, 0.18f, 0.21f};
      o.spec.height = oh;
      o.spec.width = ow;
      o.spec.resize_filter = filter;
      o.spec.mean = o.mean;
      o.spec.std = o.stdev;
      auto plan = PreprocessPlan::create(o.spec, w, h, 3);
      ASSERT_TRUE(plan.ok());
      std::vector<uint8_t> pixels(static_cast<size_t>(ow * oh * 3));
      ASSERT_TRUE(plan->resize(frame.view(), pixels).ok());
      std::vector<float> x(plan->output_values());
      ASSERT_TRUE(plan->run(frame.view(), std::span<float>(x)).ok());
      for (size_t i = 0; i < x.size(); ++i) {
        const size_t c = i % 3;
        ASSERT_EQ(x[i], (static_cast<float>(pixels[i]) / 255.0f - o.mean[c]) / o.stdev[c])
            << "filter " << resize_filter_name(filter) << " value " << i;
      }
      auto copy = resize(frame.view(), oh, ow, filter);
      ASSERT_TRUE(copy.ok());
      EXPECT_EQ(copy->pixels, pixels);
      std::vector<uint8_t> short_buffer(pixels.size() - 1);
      EXPECT_EQ(plan->resize(frame.view(), short_buffer).error().code(), ErrorCode::kShapeMismatch);
    }
  }
}

TEST(ImagePreprocessPlan, Int8EncodingIsTheQuantizeOperatorOfTheFloatValues) {
  testing::Rng rng(11);
  const Image frame = random_image(rng, 40, 30, 3);
  OwnedSpec o = random_spec(rng, 40, 30);
  const InputEncoding enc{DType::kInt8, 0.03f, -5};
  auto f = PreprocessPlan::create(o.spec, 40, 30, 3);
  auto q = PreprocessPlan::create(o.spec, 40, 30, 3, enc);
  ASSERT_TRUE(f.ok() && q.ok());
  std::vector<float> x(f->output_values());
  std::vector<std::byte> y(q->output_bytes());
  ASSERT_TRUE(f->run(frame.view(), std::span<float>(x)).ok());
  ASSERT_TRUE(q->run(frame.view(), std::span<std::byte>(y)).ok());
  ASSERT_EQ(y.size(), x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    EXPECT_EQ(static_cast<int8_t>(y[i]), quantize_value(x[i], enc.scale, enc.zero_point)) << i;
  }
  EXPECT_EQ(q->run(frame.view(), std::span<float>(x)).error().code(), ErrorCode::kInvalidArgument);
}

TEST(ImagePreprocessPlan, ErrorsNameWhatDoesNotFit) {
  OwnedSpec o;
  o.mean = {0.5f, 0.5f, 0.5f};
  o.stdev = {0.2f, 0.2f, 0.2f};
  o.spec.height = 8;
  o.spec.width = 8;
  o.spec.mean = o.mean;
  o.spec.std = o.stdev;
  o.spec.crop_x = 4;
  o.spec.crop_w = 10;
  o.spec.crop_h = 4;
  auto bad_crop = PreprocessPlan::create(o.spec, 12, 12, 3);
  ASSERT_FALSE(bad_crop.ok());
  EXPECT_EQ(bad_crop.error().code(), ErrorCode::kShapeMismatch);
  EXPECT_STREQ(bad_crop.error().message(), "crop 4,0 10x4 does not fit the 12x12 image");
  o.spec.crop_w = 0;
  EXPECT_EQ(PreprocessPlan::create(o.spec, 12, 12, 4).error().code(), ErrorCode::kShapeMismatch);
  o.spec.background_subtraction = true;
  EXPECT_EQ(PreprocessPlan::create(o.spec, 12, 12, 3).error().code(), ErrorCode::kModelUnsupported);
  o.spec.background_subtraction = false;
  auto plan = PreprocessPlan::create(o.spec, 12, 12, 3);
  ASSERT_TRUE(plan.ok());
  testing::Rng rng(1);
  const Image wrong = random_image(rng, 12, 11, 3);
  std::vector<float> out(plan->output_values());
  auto st = plan->run(wrong.view(), std::span<float>(out));
  ASSERT_FALSE(st.ok());
  EXPECT_STREQ(st.error().message(), "frame is 12x11x3; the preprocessing was planned for 12x12x3");
  const Image right = random_image(rng, 12, 12, 3);
  std::vector<float> small(out.size() - 1);
  EXPECT_EQ(plan->run(right.view(), std::span<float>(small)).error().code(),
            ErrorCode::kShapeMismatch);
}

TEST(ImagePreprocessPlan, RunAllocatesNothing) {
  testing::Rng rng(3);
  const Image frame = random_image(rng, 320, 240, 3);
  for (ResizeFilter filter :
       {ResizeFilter::kBilinear, ResizeFilter::kArea, ResizeFilter::kNearest}) {
    const OwnedSpec o = rgb_spec(96, 128, filter, {0.5f, 0.5f, 0.5f}, {0.2f, 0.2f, 0.2f});
    auto plan = PreprocessPlan::create(o.spec, 320, 240, 3);
    ASSERT_TRUE(plan.ok());
    std::vector<std::byte> out(plan->output_bytes());
    testing::start_counting_allocations();
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(plan->run(frame.view(), out).ok());
    EXPECT_EQ(testing::stop_counting_allocations(), 0u) << static_cast<int>(filter);
  }
}

}  // namespace
}  // namespace tlvlink::image
