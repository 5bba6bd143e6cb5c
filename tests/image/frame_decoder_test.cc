// FrameDecoder: camera frames of every format into the sensor's processed RGB frame, the MJPEG
// scale it picks, orientation, and the errors a bad frame gets.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/random.h"
#include "tlvlink/image/frame_decoder.h"

namespace tlvlink::image {
namespace {

Image gradient(int32_t w, int32_t h) {
  Image img{w, h, 3, {}};
  img.pixels.resize(static_cast<size_t>(w * h * 3));
  for (int32_t y = 0; y < h; ++y)
    for (int32_t x = 0; x < w; ++x)
      for (int32_t c = 0; c < 3; ++c)
        img.pixels[static_cast<size_t>((y * w + x) * 3 + c)] =
            static_cast<uint8_t>((x * 255 / w + y * 127 / h + 60 * c) % 256);
  return img;
}

TEST(ImageFrameDecoder, PicksTheSmallestJpegScaleThatKeepsTheView) {
  // A GelSight Mini: MJPEG 3280x2464, 15 % cut from each border, into 320x240 -> 1/8 (the view
  // keeps 287x216, 90 % of each axis). A 320x240 MJPEG camera decodes at 1/1.
  const SensorView mini{320, 240, 0.15, Orientation::kUpright, 0};
  auto d = FrameDecoder::create({PixelFormat::kMjpeg, 3280, 2464, 0}, mini);
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->jpeg_scale_denominator(), 8);
  auto small = FrameDecoder::create({PixelFormat::kMjpeg, 320, 240, 0}, {320, 240, 0, {}, 0});
  ASSERT_TRUE(small.ok());
  EXPECT_EQ(small->jpeg_scale_denominator(), 1);
  EXPECT_FALSE(
      FrameDecoder::create({PixelFormat::kMjpeg, 320, 240, 0}, {320, 240, 0.5, {}, 0}).ok());
  EXPECT_FALSE(FrameDecoder::create({PixelFormat::kMjpeg, 320, 240, 0}, {320, 240, 0, {}, 3}).ok());
}

TEST(ImageFrameDecoder, AFrameOfAnotherAspectIsRefusedNotStretched) {
  // A 300x400 portrait frame into the Mini's 320x240 view would be squashed to a third of its
  // height: an error naming both sizes. A Mini's own 3280x2464 (aspect 1.331 vs 1.333) and a
  // DIGIT's transposed 320x240 pass.
  auto portrait = FrameDecoder::create({PixelFormat::kRgb24, 300, 400, 0}, {320, 240, 0, {}, 0});
  ASSERT_FALSE(portrait.ok());
  EXPECT_EQ(portrait.error().code(), ErrorCode::kShapeMismatch);
  const std::string m = portrait.error().message();
  EXPECT_NE(m.find("300x400"), std::string::npos) << m;
  EXPECT_NE(m.find("320x240"), std::string::npos) << m;
  EXPECT_FALSE(FrameDecoder::create({PixelFormat::kMjpeg, 640, 360, 0},
                                    {320, 240, 0.15, Orientation::kUpright, 0})
                   .ok());  // 16:9 into 4:3
  EXPECT_TRUE(FrameDecoder::create({PixelFormat::kMjpeg, 3280, 2464, 0},
                                   {320, 240, 0.15, Orientation::kUpright, 0})
                  .ok());
  EXPECT_TRUE(FrameDecoder::create({PixelFormat::kYuyv, 320, 240, 0},
                                   {240, 320, 0, Orientation::kTransposed, 0})
                  .ok());
  EXPECT_TRUE(FrameDecoder::create({PixelFormat::kRgb24, 640, 480, 0}, {320, 240, 0, {}, 0}).ok());
}

TEST(ImageFrameDecoder, MjpegAtFullScaleWithoutCropIsTheJpegDecode) {
  const Image img = gradient(64, 48);
  auto jpeg = encode_jpeg(img, 95);
  ASSERT_TRUE(jpeg.ok());
  auto want = decode_jpeg(*jpeg, "ref");
  ASSERT_TRUE(want.ok());
  auto d = FrameDecoder::create({PixelFormat::kMjpeg, 64, 48, 0}, {64, 48, 0, {}, 0});
  ASSERT_TRUE(d.ok());
  std::vector<uint8_t> out(d->output_bytes());
  ASSERT_TRUE(d->decode(*jpeg, out, "cam").ok());
  EXPECT_EQ(out, want->pixels);
}

TEST(ImageFrameDecoder, TransposedYuyvComesBackUpright) {
  // DIGIT sends its frames transposed; here a small 8x4 camera frame whose upright view is 4x8.
  // Without crop or resize the decoder's frame is exactly the conversion's; a flat colour
  // survives the YUYV round trip within 8-bit Y/Cb/Cr steps.
  const FrameFormat cam{PixelFormat::kYuyv, 8, 4, 0};
  testing::Rng rng(5);
  std::vector<uint8_t> yuyv(8 * 4 * 2);
  for (uint8_t& b : yuyv) b = static_cast<uint8_t>(rng.int_in(16, 235));
  auto d = FrameDecoder::create(cam, {4, 8, 0, Orientation::kTransposed, 0});
  ASSERT_TRUE(d.ok());
  std::vector<uint8_t> out(d->output_bytes()), want(out.size());
  ASSERT_TRUE(d->decode(yuyv, out, "digit").ok());
  ASSERT_TRUE(camera_to_upright_rgb(yuyv, cam, Orientation::kTransposed, want, "digit").ok());
  EXPECT_EQ(out, want);
  const std::vector<uint8_t> flat(4 * 8 * 3, 140);
  ASSERT_TRUE(upright_rgb_to_camera(flat, cam, Orientation::kTransposed, yuyv).ok());
  ASSERT_TRUE(d->decode(yuyv, out, "digit").ok());
  for (size_t i = 0; i < out.size(); ++i) EXPECT_NEAR(out[i], 140, 1) << i;
}

TEST(ImageFrameDecoder, BadFramesAreFormatErrorsAndTheNextGoodFrameDecodes) {
  const Image img = gradient(64, 48);
  auto jpeg = encode_jpeg(img, 90);
  ASSERT_TRUE(jpeg.ok());
  auto d = FrameDecoder::create({PixelFormat::kMjpeg, 64, 48, 0}, {32, 24, 0.1, {}, 0});
  ASSERT_TRUE(d.ok());
  std::vector<uint8_t> out(d->output_bytes());
  const std::vector<uint8_t> truncated(jpeg->begin(), jpeg->begin() + jpeg->size() / 2);
  const std::vector<uint8_t> empty;
  const std::vector<uint8_t> junk(100, 0x5a);
  for (const auto* bad : {&truncated, &empty, &junk}) {
    auto st = d->decode(*bad, out, "mini-left frame 7");
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().code(), ErrorCode::kFormat);
    EXPECT_NE(std::string(st.error().message()).find("mini-left frame 7"), std::string::npos);
    EXPECT_TRUE(d->decode(*jpeg, out, "mini-left frame 8").ok());
  }
  auto other = encode_jpeg(gradient(32, 48), 90);
  auto st = d->decode(*other, out, "cam");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(std::string(st.error().message()).find("32x48, expected 64x48"), std::string::npos)
      << st.error().message();
  std::vector<uint8_t> wrong_out(out.size() + 1);
  EXPECT_EQ(d->decode(*jpeg, wrong_out, "cam").error().code(), ErrorCode::kShapeMismatch);
}

}  // namespace
}  // namespace tlvlink::image

namespace tlvlink::image {
namespace {

// The cropped decode (only the view and a margin) gives the frame a whole-frame decode at the same
// scale gives, resampled the same way: the IDCT of a block does not depend on its neighbours, and
// the 2-px margin keeps the crop's edge upsampling out of the resampler's reach.
TEST(ImageFrameDecoder, CroppedDecodeEqualsTheWholeFrameDecode) {
  const Image img = gradient(640, 480);
  auto jpeg = encode_jpeg(img, 90);
  ASSERT_TRUE(jpeg.ok());
  for (int32_t scale : {1, 2, 4}) {
    const SensorView view{96, 72, 0.15, Orientation::kUpright, scale};
    auto d = FrameDecoder::create({PixelFormat::kMjpeg, 640, 480, 0}, view);
    ASSERT_TRUE(d.ok());
    std::vector<uint8_t> out(d->output_bytes());
    ASSERT_TRUE(d->decode(*jpeg, out, "cam").ok());
    auto whole = decode_jpeg(*jpeg, "ref", scale);
    ASSERT_TRUE(whole.ok());
    Resampler r;
    r.plan(whole->width, whole->height, view.width, view.height,
           view_from_camera(view.crop, whole->width, view.width),
           view_from_camera(view.crop, whole->height, view.height));
    std::vector<uint8_t> want(out.size());
    r.run(whole->pixels.data(), want.data());
    int worst = 0;
    size_t differing = 0;
    for (size_t i = 0; i < out.size(); ++i) {
      const int diff = std::abs(static_cast<int>(out[i]) - static_cast<int>(want[i]));
      worst = std::max(worst, diff);
      differing += diff != 0 ? 1 : 0;
    }
    std::printf("scale 1/%d: %zu of %zu values differ, at most %d\n", scale, differing, out.size(),
                worst);
    // At full scale the 4:2:0 chroma's vertical upsampling at the region's first rows uses a row
    // the skip reconstructs differently (measured: 2 of 20,736 values, 1 DN). Scaled decodes
    // (every real use: a Mini decodes at 1/8) are identical.
    constexpr int kFullScaleUpsamplingDn = 1;
    EXPECT_LE(worst, scale == 1 ? kFullScaleUpsamplingDn : 0) << "scale 1/" << scale;
  }
}

}  // namespace
}  // namespace tlvlink::image
