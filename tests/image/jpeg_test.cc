// JPEG encode/decode through libturbojpeg: round trips, scaled decodes, broken streams, limits.

#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/image.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "support/random.h"

namespace tlvlink::tools {
namespace {

using image::decode_jpeg;
using image::encode_jpeg;
using image::kMaxJpegSide;

// q=100 with 4:2:0 chroma subsampling: a smooth image loses well under 1 DN on average (the
// chroma is halved, not quantized away); single pixels at colour edges may move a few DN.
constexpr double kQ100MeanAbsTolerance = 1.0;
constexpr int kQ100MaxAbsTolerance = 12;

Image smooth(int32_t h, int32_t w, int32_t channels, uint64_t seed) {
  testing::Rng rng(seed);
  const float a = rng.uniform(0.02f, 0.1f), b = rng.uniform(0.02f, 0.1f);
  Image img;
  img.height = h;
  img.width = w;
  img.channels = channels;
  img.pixels.resize(static_cast<size_t>(h * w * channels));
  for (int32_t y = 0; y < h; ++y)
    for (int32_t x = 0; x < w; ++x)
      for (int32_t c = 0; c < channels; ++c)
        img.pixels[static_cast<size_t>((y * w + x) * channels + c)] = static_cast<uint8_t>(
            std::lround(128.0 + 80.0 * std::sin(static_cast<double>(a) * x + c) *
                                    std::cos(static_cast<double>(b) * y)));
  return img;
}

void expect_close(const Image& a, const Image& b, double mean_tol, int max_tol) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  double sum = 0;
  int worst = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const int d = std::abs(int{a.pixels[i]} - int{b.pixels[i]});
    sum += d;
    worst = std::max(worst, d);
  }
  EXPECT_LE(sum / static_cast<double>(a.pixels.size()), mean_tol);
  EXPECT_LE(worst, max_tol);
}

TEST(Jpeg, Quality100RoundTripIsClose) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  const Image img = smooth(48, 64, 3, seed);
  auto bytes = encode_jpeg(img, 100);
  ASSERT_TRUE(bytes.ok()) << bytes.error().message();
  auto back = decode_jpeg(bytes.value(), "roundtrip");
  ASSERT_TRUE(back.ok()) << back.error().message();
  EXPECT_EQ(back->channels, 3);
  expect_close(img, back.value(), kQ100MeanAbsTolerance, kQ100MaxAbsTolerance);
}

// Colour that changes every pixel (how a GelSight shows fine surface normals): 4:2:0 averages
// each 2x2 block's colour away; 4:4:4 at q100 keeps it. Tolerances: q100's quantisation and the
// YCbCr round trip move a pixel by at most a few DN; the 4:2:0 loss here is tens of DN.
TEST(Jpeg, FullChromaKeepsColourDetailThatSubsamplingLoses) {
  Image img;
  img.width = 64;
  img.height = 48;
  img.channels = 3;
  img.pixels.resize(64 * 48 * 3);
  for (int32_t y = 0; y < 48; ++y)
    for (int32_t x = 0; x < 64; ++x) {
      uint8_t* p = &img.pixels[static_cast<size_t>((y * 64 + x) * 3)];
      const bool odd = ((x + y) & 1) != 0;
      p[0] = odd ? 170 : 90;  // red and blue swap, green holds the luma nearly level
      p[1] = 128;
      p[2] = odd ? 90 : 170;
    }
  auto full = encode_jpeg(img, 100, /*full_chroma=*/true);
  auto halved = encode_jpeg(img, 100);
  ASSERT_TRUE(full.ok() && halved.ok());
  auto full_back = decode_jpeg(full.value(), "4:4:4");
  auto halved_back = decode_jpeg(halved.value(), "4:2:0");
  ASSERT_TRUE(full_back.ok() && halved_back.ok());
  expect_close(img, full_back.value(), 1.0, 4);
  double halved_error = 0;
  for (size_t i = 0; i < img.pixels.size(); ++i)
    halved_error += std::abs(int{img.pixels[i]} - int{halved_back->pixels[i]});
  EXPECT_GT(halved_error / static_cast<double>(img.pixels.size()), 10.0);
}

TEST(Jpeg, GrayEncodesAndDecodesAsRgb) {
  const Image gray = smooth(24, 40, 1, 7);
  auto bytes = encode_jpeg(gray, 100);
  ASSERT_TRUE(bytes.ok()) << bytes.error().message();
  auto back = decode_jpeg(bytes.value(), "gray");
  ASSERT_TRUE(back.ok()) << back.error().message();
  ASSERT_EQ(back->channels, 3);
  Image as_rgb = gray;
  as_rgb.channels = 3;
  as_rgb.pixels.clear();
  for (uint8_t v : gray.pixels) as_rgb.pixels.insert(as_rgb.pixels.end(), {v, v, v});
  expect_close(as_rgb, back.value(), kQ100MeanAbsTolerance, kQ100MaxAbsTolerance);
}

TEST(Jpeg, Quality1StillDecodes) {
  const Image img = smooth(30, 50, 3, 3);
  auto q1 = encode_jpeg(img, 1);
  auto q100 = encode_jpeg(img, 100);
  ASSERT_TRUE(q1.ok() && q100.ok());
  EXPECT_LT(q1->size(), q100->size());
  auto back = decode_jpeg(q1.value(), "q1");
  ASSERT_TRUE(back.ok()) << back.error().message();
  EXPECT_EQ(back->width, 50);
  EXPECT_EQ(back->height, 30);
}

TEST(Jpeg, ScaledDecodeSizes) {
  const Image img = smooth(480, 640, 3, 5);
  auto bytes = encode_jpeg(img, 90);
  ASSERT_TRUE(bytes.ok());
  for (int32_t d : {1, 2, 4, 8}) {
    auto back = decode_jpeg(bytes.value(), "scaled", d);
    ASSERT_TRUE(back.ok()) << back.error().message();
    EXPECT_EQ(back->width, 640 / d);
    EXPECT_EQ(back->height, 480 / d);
    EXPECT_EQ(back->pixels.size(), static_cast<size_t>(640 / d * 480 / d * 3));
  }
  // Odd sizes round up (libjpeg's ceil(dim / d)).
  auto odd = encode_jpeg(smooth(17, 33, 3, 1), 90);
  ASSERT_TRUE(odd.ok());
  auto half = decode_jpeg(odd.value(), "odd", 2);
  ASSERT_TRUE(half.ok());
  EXPECT_EQ(half->width, 17);
  EXPECT_EQ(half->height, 9);
  auto bad = decode_jpeg(odd.value(), "odd", 3);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code(), ErrorCode::kInvalidArgument);
}

TEST(Jpeg, TruncatedStreamIsAnErrorNamingTheStream) {
  auto bytes = encode_jpeg(smooth(64, 64, 3, 9), 90);
  ASSERT_TRUE(bytes.ok());
  for (size_t keep : {bytes->size() / 2, bytes->size() - 2, size_t{20}}) {
    std::vector<uint8_t> cut(bytes->begin(), bytes->begin() + static_cast<std::ptrdiff_t>(keep));
    auto back = decode_jpeg(cut, "camera 0 frame 17");
    ASSERT_FALSE(back.ok()) << "kept " << keep << " of " << bytes->size();
    EXPECT_EQ(back.error().code(), ErrorCode::kFormat);
    EXPECT_NE(std::string(back.error().message()).find("camera 0 frame 17"), std::string::npos)
        << back.error().message();
  }
}

TEST(Jpeg, GarbageAndEmptyAreErrors) {
  testing::Rng rng(11);
  std::vector<uint8_t> junk(500);
  for (auto& b : junk) b = static_cast<uint8_t>(rng.int_in(0, 255));
  auto a = decode_jpeg(junk, "junk.jpg");
  ASSERT_FALSE(a.ok());
  EXPECT_NE(std::string(a.error().message()).find("junk.jpg"), std::string::npos);
  auto b = decode_jpeg({}, "empty.jpg");
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(b.error().code(), ErrorCode::kFormat);
}

TEST(Jpeg, SizeLimits) {
  // A header claiming a side over the limit is refused before anything is allocated.
  auto bytes = encode_jpeg(smooth(16, 16, 3, 2), 90);
  ASSERT_TRUE(bytes.ok());
  std::vector<uint8_t> patched = bytes.value();
  bool found = false;
  for (size_t i = 0; i + 8 < patched.size(); ++i) {
    if (patched[i] == 0xFF && patched[i + 1] == 0xC0) {  // SOF0: len(2) precision(1) h(2) w(2)
      patched[i + 7] = 0x4E;                             // width 20000
      patched[i + 8] = 0x20;
      found = true;
      break;
    }
  }
  ASSERT_TRUE(found);
  auto big = decode_jpeg(patched, "big.jpg");
  ASSERT_FALSE(big.ok());
  EXPECT_NE(std::string(big.error().message()).find("20000"), std::string::npos)
      << big.error().message();

  Image empty;
  empty.channels = 3;
  EXPECT_EQ(encode_jpeg(empty, 90).error().code(), ErrorCode::kInvalidArgument);
  Image wide = smooth(1, 8, 3, 1);
  wide.width = kMaxJpegSide + 1;
  EXPECT_EQ(encode_jpeg(wide, 90).error().code(), ErrorCode::kInvalidArgument);
  Image short_pixels = smooth(8, 8, 3, 1);
  short_pixels.pixels.pop_back();
  EXPECT_EQ(encode_jpeg(short_pixels, 90).error().code(), ErrorCode::kInvalidArgument);
  Image four = smooth(8, 8, 3, 1);
  four.channels = 4;
  EXPECT_EQ(encode_jpeg(four, 90).error().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(encode_jpeg(smooth(8, 8, 3, 1), 0).error().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(encode_jpeg(smooth(8, 8, 3, 1), 101).error().code(), ErrorCode::kInvalidArgument);
}

TEST(Jpeg, FilesRoundTripAndMissingFileNamesThePath) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("tlvlink_jpeg_test_" + std::to_string(getpid()) + ".jpg"))
                               .string();
  const Image img = smooth(20, 30, 3, 4);
  ASSERT_TRUE(write_jpeg(path, img, 100).ok());
  auto back = read_jpeg(path, 1);
  std::filesystem::remove(path);
  ASSERT_TRUE(back.ok()) << back.error().message();
  expect_close(img, back.value(), kQ100MeanAbsTolerance, kQ100MaxAbsTolerance);
  auto missing = read_jpeg(path, 1);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code(), ErrorCode::kIo);
  EXPECT_NE(std::string(missing.error().message()).find(path), std::string::npos);
}

}  // namespace
}  // namespace tlvlink::tools
