// Raw pixel formats and the resampler, on hand-made images: BT.601 limited-range YUYV values,
// DIGIT's orientation (transpose, then flip top to bottom), and resampling edge cases.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "raw/pixel_formats.h"
#include "raw/resample.h"

namespace tlvlink::sim::internal {
namespace {

RawLayout yuyv_layout(int32_t width, int32_t height, bool transposed) {
  RawLayout l;
  l.format = RawFormat::kYuyv;
  l.width = width;
  l.height = height;
  l.transposed = transposed;
  l.frame_bytes = static_cast<size_t>(width) * static_cast<size_t>(height) * 2;
  return l;
}

TEST(SimRenderRawFormats, YuyvIsBt601LimitedRange) {
  // One pixel pair of one colour -> Y U Y V. Reference values: BT.601, 8-bit studio range
  // (Y = 16 + 219 Y', Cb/Cr = 128 + 224 (.) / (2 (1 - K))).
  struct Case {
    uint8_t r, g, b;
    uint8_t y, cb, cr;
  };
  const Case cases[] = {{0, 0, 0, 16, 128, 128},   {255, 255, 255, 235, 128, 128},
                        {255, 0, 0, 81, 90, 240},  {0, 255, 0, 145, 54, 34},
                        {0, 0, 255, 41, 240, 110}, {128, 128, 128, 126, 128, 128}};
  const RawLayout l = yuyv_layout(2, 1, false);
  for (const Case& c : cases) {
    const uint8_t rgb[6] = {c.r, c.g, c.b, c.r, c.g, c.b};
    uint8_t yuyv[4] = {};
    upright_to_yuyv(rgb, l, yuyv);
    EXPECT_EQ(yuyv[0], c.y) << int{c.r} << "," << int{c.g} << "," << int{c.b};
    EXPECT_EQ(yuyv[1], c.cb);
    EXPECT_EQ(yuyv[2], c.y);
    EXPECT_EQ(yuyv[3], c.cr);
    uint8_t back[6] = {};
    yuyv_to_upright(yuyv, l, back);
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(back[i], rgb[i], 2) << i;  // 8-bit Y/Cb/Cr steps
  }
  // A pair shares its chroma (from the mean colour, (100, 0, 100)); each pixel keeps its own
  // luma: red (200, 0, 0) and blue (0, 0, 200) both come back magenta, the first brighter.
  const uint8_t pair[6] = {200, 0, 0, 0, 0, 200};
  uint8_t yuyv[4] = {};
  upright_to_yuyv(pair, l, yuyv);
  EXPECT_EQ(yuyv[0], 67);  // 16 + 219 * 0.299 * 200 / 255
  EXPECT_EQ(yuyv[2], 36);  // 16 + 219 * 0.114 * 200 / 255
  uint8_t back[6] = {};
  yuyv_to_upright(yuyv, l, back);
  // Y' = 59.8 and 22.8, chroma R - Y' = B - Y' = 58.7, G - Y' = -41.3 (G clips on the second).
  const int expected[6] = {118, 18, 118, 81, 0, 81};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(back[i], expected[i], 2) << i;
}

// DIGIT's interface returns cv2.flip(cv2.transpose(raw), 0): processed (x, y) = raw
// (u = W - 1 - y, v = x) with W the raw width.
TEST(SimRenderRawFormats, TransposedLayoutMatchesDigitInterface) {
  const int32_t raw_w = 4, raw_h = 2;  // raw 4 wide x 2 high -> processed 2 wide x 4 high
  RawLayout l;
  l.format = RawFormat::kRgb;
  l.width = raw_w;
  l.height = raw_h;
  l.transposed = true;
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
  raw_rgb_to_upright(raw.data(), l, upright.data());
  EXPECT_EQ(upright, expected);
  upright_to_raw_rgb(upright.data(), l, again.data());
  EXPECT_EQ(again, raw);
  // YUYV walks the same way: a grey ramp along raw u survives as luma along processed -y.
  const RawLayout y = yuyv_layout(raw_w, raw_h, true);
  std::vector<uint8_t> grey(raw.size());
  for (size_t i = 0; i < grey.size(); ++i) grey[i] = static_cast<uint8_t>(40 * (i / 3 / 2) + 20);
  std::vector<uint8_t> yuyv(y.frame_bytes), back(grey.size());
  upright_to_yuyv(grey.data(), y, yuyv.data());
  yuyv_to_upright(yuyv.data(), y, back.data());
  for (size_t i = 0; i < grey.size(); ++i) EXPECT_NEAR(back[i], grey[i], 1) << i;
}

TEST(SimRenderRawFormats, ResamplerIsExactAtScaleOneAndKeepsConstants) {
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

}  // namespace
}  // namespace tlvlink::sim::internal
