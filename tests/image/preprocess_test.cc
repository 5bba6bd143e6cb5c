// Preprocessing per InputSpec: resize, channel order, normalisation, uint8 .npy images.

#include <cmath>

#include <gtest/gtest.h>

#include "tlvlink/image/preprocess.h"
#include "tlvlink/io/npy_image.h"

namespace tlvlink::tools {
namespace {

using image::preprocess;
using image::resize_bilinear;

// Pixel arithmetic is exact up to float rounding of (v/255 - mean)/std.
constexpr float kNormTolerance = 1e-6f;

struct Spec {
  std::vector<float> mean{0.5f, 0.5f, 0.5f}, stdev{0.25f, 0.25f, 0.25f};
  InputSpec spec;
  Spec(int32_t h, int32_t w, ChannelOrder order = ChannelOrder::kRGB, int32_t channels = 3) {
    mean.resize(static_cast<size_t>(channels));
    stdev.resize(static_cast<size_t>(channels));
    spec.height = h;
    spec.width = w;
    spec.channels = channels;
    spec.channel_order = order;
    spec.mean = mean;
    spec.std = stdev;
  }
};

Image solid(int32_t w, int32_t h, uint8_t r, uint8_t g, uint8_t b) {
  Image img{w, h, 3, {}};
  for (int32_t i = 0; i < w * h; ++i) img.pixels.insert(img.pixels.end(), {r, g, b});
  return img;
}

TEST(Preprocess, NormalisesAndOrdersChannels) {
  const Image img = solid(4, 4, 0, 128, 255);
  Spec rgb(4, 4);
  auto x = preprocess(img, rgb.spec);
  ASSERT_TRUE(x.ok()) << x.error().message();
  ASSERT_EQ(x->size(), 48u);
  EXPECT_NEAR((*x)[0], (0.0f - 0.5f) / 0.25f, kNormTolerance);
  EXPECT_NEAR((*x)[1], (128.0f / 255.0f - 0.5f) / 0.25f, kNormTolerance);
  EXPECT_NEAR((*x)[2], (1.0f - 0.5f) / 0.25f, kNormTolerance);
  Spec bgr(4, 4, ChannelOrder::kBGR);
  auto y = preprocess(img, bgr.spec);
  ASSERT_TRUE(y.ok());
  EXPECT_NEAR((*y)[0], 2.0f, kNormTolerance);
  EXPECT_NEAR((*y)[2], -2.0f, kNormTolerance);
}

TEST(Preprocess, ResizesBilinearWithHalfPixelCentres) {
  // A horizontal ramp 0..255 over 8 pixels, halved: each output is the mean of two neighbours.
  Image ramp{8, 2, 1, {}};
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 8; ++x) ramp.pixels.push_back(static_cast<uint8_t>(x * 30));
  const Image half = resize_bilinear(ramp, 1, 4);
  ASSERT_EQ(half.pixels.size(), 4u);
  EXPECT_EQ(half.pixels[0], 15);
  EXPECT_EQ(half.pixels[3], 195);
  // Constant images stay constant under any resize.
  const Image big = resize_bilinear(solid(5, 3, 9, 99, 199), 17, 11);
  for (size_t i = 0; i < big.pixels.size(); i += 3) {
    ASSERT_EQ(big.pixels[i], 9);
    ASSERT_EQ(big.pixels[i + 2], 199);
  }
}

TEST(Preprocess, GrayImageFeedsRgbModelAndBackgroundSubtractionIsRefused) {
  Image gray{2, 2, 1, {10, 20, 30, 40}};
  Spec rgb(2, 2);
  auto x = preprocess(gray, rgb.spec);
  ASSERT_TRUE(x.ok());
  EXPECT_FLOAT_EQ((*x)[0], (*x)[1]);
  rgb.spec.background_subtraction = true;
  auto r = preprocess(gray, rgb.spec);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(std::string(r.error().message()).find("background subtraction"), std::string::npos);
}

TEST(Preprocess, ImageFromNpyAcceptsHwcAndNhwcOnly) {
  std::vector<uint8_t> px(2 * 3 * 3, 7);
  EXPECT_TRUE(image_from_npy(NpyArray::from<uint8_t>({2, 3, 3}, px), "a.npy").ok());
  auto b = image_from_npy(NpyArray::from<uint8_t>({1, 2, 3, 3}, px), "b.npy");
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(b->width, 3);
  EXPECT_EQ(b->height, 2);
  auto bad = image_from_npy(NpyArray::from<uint8_t>({2, 9}, px), "c.npy");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(std::string(bad.error().message()).find("c.npy"), std::string::npos);
  EXPECT_FALSE(image_from_npy(NpyArray::from<uint8_t>({2, 1, 3, 3}, px), "d.npy").ok());
  std::vector<float> f(18);
  EXPECT_FALSE(image_from_npy(NpyArray::from<float>({2, 3, 3}, f), "e.npy").ok());
}

}  // namespace
}  // namespace tlvlink::tools
