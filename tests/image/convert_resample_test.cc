// Camera pixel formats and the resampler, on hand-made images: BT.601 limited-range YUYV and
// NV12 values, GREY, padded rows, DIGIT's orientation (transpose, then flip top to bottom), and
// resampling edge cases.
#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/image/convert.h"
#include "tlvlink/image/resample.h"

namespace tlvlink::image {
namespace {

constexpr Orientation kUp = Orientation::kUpright, kTr = Orientation::kTransposed;

// The converters on raw pointers of the sizes the tests use.
void upright_to_yuyv(const uint8_t* rgb, int32_t w, int32_t h, Orientation o, uint8_t* yuyv) {
  const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
  ASSERT_TRUE(
      upright_rgb_to_camera({rgb, n * 3}, {PixelFormat::kYuyv, w, h, 0}, o, {yuyv, n * 2}).ok());
}
void yuyv_to_upright(const uint8_t* yuyv, int32_t w, int32_t h, Orientation o, uint8_t* rgb) {
  const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
  ASSERT_TRUE(
      camera_to_upright_rgb({yuyv, n * 2}, {PixelFormat::kYuyv, w, h, 0}, o, {rgb, n * 3}, "test")
          .ok());
}

TEST(ImageConvert, YuyvIsBt601LimitedRange) {
  // One pixel pair of one colour -> Y U Y V. Reference values: BT.601, 8-bit studio range
  // (Y = 16 + 219 Y', Cb/Cr = 128 + 224 (.) / (2 (1 - K))).
  struct Case {
    uint8_t r, g, b;
    uint8_t y, cb, cr;
  };
  const Case cases[] = {{0, 0, 0, 16, 128, 128},   {255, 255, 255, 235, 128, 128},
                        {255, 0, 0, 81, 90, 240},  {0, 255, 0, 145, 54, 34},
                        {0, 0, 255, 41, 240, 110}, {128, 128, 128, 126, 128, 128}};
  for (const Case& c : cases) {
    const uint8_t rgb[6] = {c.r, c.g, c.b, c.r, c.g, c.b};
    uint8_t yuyv[4] = {};
    upright_to_yuyv(rgb, 2, 1, kUp, yuyv);
    EXPECT_EQ(yuyv[0], c.y) << int{c.r} << "," << int{c.g} << "," << int{c.b};
    EXPECT_EQ(yuyv[1], c.cb);
    EXPECT_EQ(yuyv[2], c.y);
    EXPECT_EQ(yuyv[3], c.cr);
    uint8_t back[6] = {};
    yuyv_to_upright(yuyv, 2, 1, kUp, back);
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(back[i], rgb[i], 2) << i;  // 8-bit Y/Cb/Cr steps
  }
  // A pair shares its chroma (from the mean colour, (100, 0, 100)); each pixel keeps its own
  // luma: red (200, 0, 0) and blue (0, 0, 200) both come back magenta, the first brighter.
  const uint8_t pair[6] = {200, 0, 0, 0, 0, 200};
  uint8_t yuyv[4] = {};
  upright_to_yuyv(pair, 2, 1, kUp, yuyv);
  EXPECT_EQ(yuyv[0], 67);  // 16 + 219 * 0.299 * 200 / 255
  EXPECT_EQ(yuyv[2], 36);  // 16 + 219 * 0.114 * 200 / 255
  uint8_t back[6] = {};
  yuyv_to_upright(yuyv, 2, 1, kUp, back);
  // Y' = 59.8 and 22.8, chroma R - Y' = B - Y' = 58.7, G - Y' = -41.3 (G clips on the second).
  const int expected[6] = {118, 18, 118, 81, 0, 81};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(back[i], expected[i], 2) << i;
}

// DIGIT's interface returns cv2.flip(cv2.transpose(raw), 0): processed (x, y) = raw
// (u = W - 1 - y, v = x) with W the raw width.
TEST(ImageConvert, TransposedLayoutMatchesDigitInterface) {
  const int32_t raw_w = 4, raw_h = 2;  // raw 4 wide x 2 high -> processed 2 wide x 4 high
  const FrameFormat rgb24{PixelFormat::kRgb24, raw_w, raw_h, 0};
  std::vector<uint8_t> raw(static_cast<size_t>(raw_w * raw_h * 3));
  for (int32_t v = 0; v < raw_h; ++v) {
    for (int32_t u = 0; u < raw_w; ++u) {
      for (int c = 0; c < 3; ++c)
        raw[static_cast<size_t>((v * raw_w + u) * 3 + c)] =
            static_cast<uint8_t>(10 * v + u + 100 * c);
    }
  }
  // The interface's two steps, written out.
  std::vector<uint8_t> transposed(raw.size()), expected(raw.size());
  for (int32_t v = 0; v < raw_h; ++v) {  // transpose: T(x = v, y = u), T is raw_h wide
    for (int32_t u = 0; u < raw_w; ++u) {
      for (int c = 0; c < 3; ++c)
        transposed[static_cast<size_t>((u * raw_h + v) * 3 + c)] =
            raw[static_cast<size_t>((v * raw_w + u) * 3 + c)];
    }
  }
  for (int32_t y = 0; y < raw_w; ++y) {  // flip(.., 0): rows reversed
    for (int32_t x = 0; x < raw_h * 3; ++x) {
      expected[static_cast<size_t>(y * raw_h * 3 + x)] =
          transposed[static_cast<size_t>((raw_w - 1 - y) * raw_h * 3 + x)];
    }
  }
  std::vector<uint8_t> upright(raw.size()), again(raw.size());
  ASSERT_TRUE(camera_to_upright_rgb(raw, rgb24, kTr, upright, "test").ok());
  EXPECT_EQ(upright, expected);
  ASSERT_TRUE(upright_rgb_to_camera(upright, rgb24, kTr, again).ok());
  EXPECT_EQ(again, raw);
  // YUYV walks the same way: a grey ramp along raw u survives as luma along processed -y.
  std::vector<uint8_t> grey(raw.size());
  for (size_t i = 0; i < grey.size(); ++i) grey[i] = static_cast<uint8_t>(40 * (i / 3 / 2) + 20);
  std::vector<uint8_t> yuyv(static_cast<size_t>(raw_w * raw_h * 2)), back(grey.size());
  upright_to_yuyv(grey.data(), raw_w, raw_h, kTr, yuyv.data());
  yuyv_to_upright(yuyv.data(), raw_w, raw_h, kTr, back.data());
  for (size_t i = 0; i < grey.size(); ++i) EXPECT_NEAR(back[i], grey[i], 1) << i;
}

TEST(ImageResample, ResamplerIsExactAtScaleOneAndKeepsConstants) {
  const int32_t w = 7, h = 5;
  std::vector<uint8_t> img(static_cast<size_t>(w * h * 3));
  for (size_t i = 0; i < img.size(); ++i) img[i] = static_cast<uint8_t>(i * 37 % 251);
  Resampler same;
  same.plan(w, h, w, h, {0, 1}, {0, 1});
  std::vector<uint8_t> out(img.size());
  same.run(img.data(), out.data());
  EXPECT_EQ(out, img);
  // Enlarging and shrinking (with a crop and with reads past the edge) keep a flat image flat.
  const std::vector<uint8_t> flat(static_cast<size_t>(w * h * 3), 173);
  for (auto [dw, dh, map] :
       {std::tuple{40, 30, AxisMap{-2, 0.3}}, std::tuple{3, 2, AxisMap{1, 1.7}}}) {
    Resampler r;
    r.plan(w, h, dw, dh, map, map);
    std::vector<uint8_t> o(static_cast<size_t>(dw * dh * 3));
    r.run(flat.data(), o.data());
    for (uint8_t v : o) ASSERT_EQ(v, 173);
  }
  // Shrinking by 2 averages: a 1-px checkerboard of 0/200 becomes ~100 everywhere.
  std::vector<uint8_t> checker(static_cast<size_t>(8 * 8 * 3));
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      for (int c = 0; c < 3; ++c)
        checker[static_cast<size_t>((y * 8 + x) * 3 + c)] = (x + y) % 2 ? 200 : 0;
    }
  }
  Resampler half;
  half.plan(8, 8, 4, 4, {0, 2}, {0, 2});
  std::vector<uint8_t> small(4 * 4 * 3);
  half.run(checker.data(), small.data());
  for (uint8_t v : small) EXPECT_NEAR(v, 100, 13);  // tent weights 1/4, 3/4, 3/4, 1/4 per axis
}

// The resampler against the tent filter computed directly in double, on random pixels: enlarging
// (two rows per destination row, the simulator's camera frames) and shrinking (more), with rows
// whose length is not a multiple of the 16 bytes the vector path takes at a time. Within 1 DN:
// the resampler sums in float, and a float sum may round to the other side of a half.
TEST(ImageResample, ResamplerMatchesTheTentFilterOnRandomPixels) {
  const auto tent = [](int32_t src_len, AxisMap map, int32_t i) {
    const double s = map.offset + (i + 0.5) * map.scale - 0.5, support = std::max(1.0, map.scale);
    std::vector<std::pair<int32_t, double>> taps;
    double sum = 0;
    for (auto j = static_cast<int32_t>(std::ceil(s - support)); j <= std::floor(s + support); ++j) {
      const double w = 1 - std::fabs(j - s) / support;
      if (w <= 0) continue;
      taps.emplace_back(std::clamp(j, 0, src_len - 1), w);
      sum += w;
    }
    for (auto& t : taps) t.second /= sum;
    return taps;
  };
  const int32_t w = 23, h = 17;
  std::vector<uint8_t> img(static_cast<size_t>(w * h * 3));
  uint32_t state = 12345;
  for (uint8_t& v : img) v = static_cast<uint8_t>((state = state * 1664525u + 1013904223u) >> 24);
  for (auto [dw, dh, xm, ym] : {std::tuple{61, 45, AxisMap{0.5, 0.35}, AxisMap{-1, 0.4}},
                                std::tuple{7, 5, AxisMap{0, 3.2}, AxisMap{0.3, 3.3}}}) {
    Resampler r;
    r.plan(w, h, dw, dh, xm, ym);
    std::vector<uint8_t> out(static_cast<size_t>(dw * dh * 3));
    r.run(img.data(), out.data());
    for (int32_t y = 0; y < dh; ++y) {
      for (int32_t x = 0; x < dw; ++x) {
        for (int32_t c = 0; c < 3; ++c) {
          double v = 0;
          for (auto [sy, wy] : tent(h, ym, y))
            for (auto [sx, wx] : tent(w, xm, x))
              v += wy * wx * img[static_cast<size_t>((sy * w + sx) * 3 + c)];
          ASSERT_NEAR(out[static_cast<size_t>((y * dw + x) * 3 + c)], std::round(v), 1)
              << dw << "x" << dh << " at " << x << "," << y << " channel " << c;
        }
      }
    }
  }
}

// NV12: the Y plane, then U/V interleaved at half resolution; every 2x2 block shares its chroma.
// GREY replicates luma. Padded rows (bytesperline > width * bpp) are honoured.
TEST(ImageConvert, Nv12GreyAndPaddedRows) {
  // A 4x2 NV12 frame: luma ramp, one chroma pair per 2x2 block (grey, then "red").
  const int32_t w = 4, h = 2;
  std::vector<uint8_t> nv12 = {16,  100, 180, 235, 16, 100, 180, 235,  // Y rows
                               128, 128, 90,  240};                    // U V | U V
  std::vector<uint8_t> rgb(static_cast<size_t>(w * h * 3));
  ASSERT_TRUE(camera_to_upright_rgb(nv12, {PixelFormat::kNv12, w, h, 0}, kUp, rgb, "nv12").ok());
  EXPECT_EQ(rgb[0], 0);  // Y 16, no chroma: black
  // Y 235 with Cb 90, Cr 240 (reddish): R clips, G = 255 + 0.392 * 38 - 0.813 * 112 = 179.
  EXPECT_EQ(rgb[3 * 3 + 0], 255);
  EXPECT_EQ(rgb[3 * 3 + 1], 179);
  for (size_t i = 0; i < 12; ++i) EXPECT_EQ(rgb[i], rgb[12 + i]) << i;  // rows share the chroma
  // The same Y, Cb, Cr through YUYV (a pair shares chroma as a 2x2 block does) give the same row.
  std::vector<uint8_t> yuyv = {16, 128, 100, 128, 180, 90, 235, 240};
  std::vector<uint8_t> row(static_cast<size_t>(w * 3));
  ASSERT_TRUE(camera_to_upright_rgb(yuyv, {PixelFormat::kYuyv, w, 1, 0}, kUp, row, "yuyv").ok());
  for (size_t i = 0; i < row.size(); ++i) EXPECT_EQ(row[i], rgb[i]) << i;
  // GREY with 2 bytes of padding per row.
  std::vector<uint8_t> grey = {10, 20, 30, 0, 0, 40, 50, 60, 0, 0};
  std::vector<uint8_t> g(3 * 2 * 3);
  ASSERT_TRUE(camera_to_upright_rgb(grey, {PixelFormat::kGrey, 3, 2, 5}, kUp, g, "grey").ok());
  const uint8_t want[6] = {10, 20, 30, 40, 50, 60};
  for (size_t p = 0; p < 6; ++p)
    for (size_t c = 0; c < 3; ++c) EXPECT_EQ(g[p * 3 + c], want[p]) << p;
}

TEST(ImageConvert, ShortFramesAndMjpegAreErrorsNamingTheStream) {
  std::vector<uint8_t> rgb(4 * 2 * 3);
  std::vector<uint8_t> short_yuyv(4 * 2 * 2 - 1);
  auto st = camera_to_upright_rgb(short_yuyv, {PixelFormat::kYuyv, 4, 2, 0}, kUp, rgb, "cam0");
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code(), ErrorCode::kFormat);
  EXPECT_NE(std::string(st.error().message()).find("cam0: 15 bytes"), std::string::npos)
      << st.error().message();
  std::vector<uint8_t> odd(3 * 2 * 2);
  EXPECT_FALSE(camera_to_upright_rgb(odd, {PixelFormat::kYuyv, 3, 2, 0}, kUp, rgb, "odd").ok());
  EXPECT_EQ(
      camera_to_upright_rgb(odd, {PixelFormat::kMjpeg, 4, 2, 0}, kUp, rgb, "m").error().code(),
      ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace tlvlink::image
