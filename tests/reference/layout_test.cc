// GlobalAveragePool, MaxPool2D, Pad, Reshape, ResizeBilinear, Quantize and Dequantize.
#include <algorithm>
#include <cmath>

#include "reference/ref_util.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::reference_test {
namespace {

// Averages and bilinear blends of O(1) values: a few float32 roundings (~1e-7 each).
constexpr double kFloatTolerance = 1e-5;

using Dims = std::vector<int32_t>;

size_t count(const Dims& d) {
  size_t n = 1;
  for (int32_t v : d) n *= static_cast<size_t>(v);
  return n;
}

std::vector<std::byte> single_op(OpType type, DType dtype, const Dims& in, const Dims& out,
                                 OpParams params, QParams qx = {}, QParams qy = {}) {
  auto spec = [&](DType d, QParams q) { return d == DType::kInt8 ? q.spec() : QuantSpec{}; };
  const DType out_dtype = type == OpType::kQuantize     ? DType::kInt8
                          : type == OpType::kDequantize ? DType::kFloat32
                                                        : dtype;
  ModelBuilder m;
  const int32_t x = m.add_activation("x", dtype, in, spec(dtype, qx));
  const int32_t y = m.add_activation("y", out_dtype, out, spec(out_dtype, qy));
  m.add_op(type, "op", {x}, y, params);
  m.set_inputs({x});
  m.set_outputs({y});
  return m.finish();
}

// ---- GlobalAveragePool ----

TEST(ReferenceGlobalAveragePool, Float32HandComputed) {
  // [1, 2, 2, 2]: channel 0 = 1, 2, 3, 4; channel 1 = 10, 20, 30, 40.
  EXPECT_EQ(run1<float>(single_op(OpType::kGlobalAveragePool, DType::kFloat32, {1, 2, 2, 2},
                                  {1, 1, 1, 2}, NoParams{}),
                        std::vector<float>{1, 10, 2, 20, 3, 30, 4, 40}),
            (std::vector<float>{2.5f, 25}));
}

TEST(ReferenceGlobalAveragePool, Int8MatchesDequantizedMeanWithin1Lsb) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  const Dims in{2, 7, 5, 6};
  const QParams qx{0.05f, -7}, qy{0.01f, 4};  // narrow output: means near the rails saturate
  auto x = rng.int8s(count(in));
  // Channel 0 of batch 0 all 127, channel 1 all -128: means at both rails.
  for (size_t p = 0; p < 35; ++p) x[p * 6] = 127, x[p * 6 + 1] = -128;
  const auto y = run1<int8_t>(
      single_op(OpType::kGlobalAveragePool, DType::kInt8, in, {2, 1, 1, 6}, NoParams{}, qx, qy), x);
  std::vector<int8_t> expected;
  for (int n = 0; n < 2; ++n) {
    for (int c = 0; c < 6; ++c) {
      double sum = 0;
      for (int p = 0; p < 35; ++p) sum += qx.real(x[(static_cast<size_t>(n) * 35 + p) * 6 + c]);
      expected.push_back(quantize_double(sum / 35, qy));
    }
  }
  expect_int8_near(y, expected, kInt8Tolerance, "int8 global average pool");
  ASSERT_EQ(y.size(), 12u);
  EXPECT_EQ(y[0], 127);
  EXPECT_EQ(y[1], -128);
}

// ---- MaxPool2D ----

// Independent max pool: only positions inside the input take part.
template <typename T>
std::vector<T> max_pool_naive(const std::vector<T>& x, const Dims& in, const Pool2DParams& p,
                              const Dims& out) {
  std::vector<T> y;
  for (int n = 0; n < out[0]; ++n)
    for (int oy = 0; oy < out[1]; ++oy)
      for (int ox = 0; ox < out[2]; ++ox)
        for (int c = 0; c < out[3]; ++c) {
          bool any = false;
          T best{};
          for (int iy = oy * p.stride_h - p.pad_top; iy < oy * p.stride_h - p.pad_top + p.pool_h;
               ++iy)
            for (int ix = ox * p.stride_w - p.pad_left;
                 ix < ox * p.stride_w - p.pad_left + p.pool_w; ++ix) {
              if (iy < 0 || ix < 0 || iy >= in[1] || ix >= in[2]) continue;
              const T v = x[((static_cast<size_t>(n) * in[1] + iy) * in[2] + ix) * in[3] + c];
              best = any ? std::max(best, v) : v;
              any = true;
            }
          y.push_back(best);
        }
  return y;
}

TEST(ReferenceMaxPool, HandComputedPaddedStrided) {
  // 3x3 input 1..9, pool 2x2 stride 2, pad 1 on top/left: windows {1}, {2,3}, {4,7}, {5,6,8,9}.
  const Pool2DParams p{2, 2, 2, 2, 1, 0, 1, 0};
  EXPECT_EQ(
      run1<float>(single_op(OpType::kMaxPool2D, DType::kFloat32, {1, 3, 3, 1}, {1, 2, 2, 1}, p),
                  std::vector<float>{-1, -2, -3, -4, -5, -6, -7, -8, -9}),
      (std::vector<float>{-1, -2, -4, -5}));
}

TEST(ReferenceMaxPool, MatchesBruteForceFloat32AndInt8) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  struct Case {
    Dims in;
    Pool2DParams p;
  };
  const Case cases[] = {{{1, 6, 6, 3}, {2, 2, 2, 2, 0, 0, 0, 0}},
                        {{2, 7, 5, 4}, {3, 3, 2, 2, 1, 1, 1, 1}},
                        {{1, 5, 8, 2}, {3, 2, 1, 3, 2, 0, 0, 1}}};
  for (const Case& c : cases) {
    const int oh = (c.in[1] + c.p.pad_top + c.p.pad_bottom - c.p.pool_h) / c.p.stride_h + 1;
    const int ow = (c.in[2] + c.p.pad_left + c.p.pad_right - c.p.pool_w) / c.p.stride_w + 1;
    const Dims out{c.in[0], oh, ow, c.in[3]};
    const auto xf = rng.floats(count(c.in), -5, -1);  // all negative: padding must not win
    EXPECT_EQ(run1<float>(single_op(OpType::kMaxPool2D, DType::kFloat32, c.in, out, c.p), xf),
              max_pool_naive(xf, c.in, c.p, out));
    const QParams q{0.1f, 2};
    const auto xq = rng.int8s(count(c.in), -128, -100);
    EXPECT_EQ(run1<int8_t>(single_op(OpType::kMaxPool2D, DType::kInt8, c.in, out, c.p, q, q), xq),
              max_pool_naive(xq, c.in, c.p, out));
  }
}

// ---- Pad and Reshape ----

TEST(ReferencePad, HandComputedRank2AndRank4) {
  PadParams p;
  p.before = {1, 0};
  p.after = {0, 2};
  p.value = 9;
  // [[1, 2], [3, 4]] -> [[9, 9, 9, 9], [1, 2, 9, 9], [3, 4, 9, 9]]
  EXPECT_EQ(run1<float>(single_op(OpType::kPad, DType::kFloat32, {2, 2}, {3, 4}, p),
                        std::vector<float>{1, 2, 3, 4}),
            (std::vector<float>{9, 9, 9, 9, 1, 2, 9, 9, 3, 4, 9, 9}));
  // NHWC spatial pad of a 1x1x2 image by one pixel on the left and bottom; int8 pad value is
  // quantize(0.5) = round(0.5 / 0.25) + 1 = 3.
  PadParams s;
  s.before = {0, 0, 1, 0};
  s.after = {0, 1, 0, 0};
  s.value = 0.5f;
  const QParams q{0.25f, 1};
  EXPECT_EQ(run1<int8_t>(single_op(OpType::kPad, DType::kInt8, {1, 1, 1, 2}, {1, 2, 2, 2}, s, q, q),
                         std::vector<int8_t>{-5, 7}),
            (std::vector<int8_t>{3, 3, -5, 7, 3, 3, 3, 3}));
}

TEST(ReferencePad, Rank6MatchesIndexArithmetic) {
  const Dims in{2, 1, 3, 2, 1, 2};
  PadParams p;
  p.before = {0, 1, 0, 2, 1, 0};
  p.after = {1, 0, 1, 0, 1, 3};
  p.value = -1;
  Dims out(6);
  for (size_t d = 0; d < 6; ++d) out[d] = in[d] + p.before[d] + p.after[d];
  std::vector<float> x(count(in));
  for (size_t i = 0; i < x.size(); ++i) x[i] = static_cast<float>(i);
  const auto y = run1<float>(single_op(OpType::kPad, DType::kFloat32, in, out, p), x);
  ASSERT_EQ(y.size(), count(out));
  for (size_t o = 0; o < y.size(); ++o) {
    size_t rem = o, src = 0;
    bool inside = true;
    std::vector<size_t> idx(6);
    for (size_t d = 6; d-- > 0;) {
      idx[d] = rem % static_cast<size_t>(out[d]);
      rem /= static_cast<size_t>(out[d]);
    }
    for (size_t d = 0; d < 6; ++d) {
      const auto i = static_cast<int64_t>(idx[d]) - p.before[d];
      inside = inside && i >= 0 && i < in[d];
      src = src * static_cast<size_t>(in[d]) + static_cast<size_t>(std::max<int64_t>(i, 0));
    }
    ASSERT_EQ(y[o], inside ? x[src] : -1.0f) << "element " << o;
  }
}

TEST(ReferenceReshape, CopiesBytes) {
  const QParams q{0.5f, -3};
  const std::vector<int8_t> x{1, -2, 3, -4, 5, -6};
  EXPECT_EQ(run1<int8_t>(
                single_op(OpType::kReshape, DType::kInt8, {1, 2, 3}, {3, 2}, NoParams{}, q, q), x),
            x);
  const std::vector<float> xf{1.5f, 2, 3, 4};
  EXPECT_EQ(
      run1<float>(single_op(OpType::kReshape, DType::kFloat32, {4}, {1, 1, 2, 2}, NoParams{}), xf),
      xf);
}

// ---- ResizeBilinear ----

// Independent bilinear sampling with the two coordinate conventions, in double.
std::vector<double> resize_naive(const std::vector<double>& x, const Dims& in, const Dims& out,
                                 bool align_corners) {
  auto src = [&](int dst, int n_in, int n_out) {
    if (align_corners) return n_out > 1 ? dst * double(n_in - 1) / (n_out - 1) : 0.0;
    return std::max(0.0, (dst + 0.5) * n_in / n_out - 0.5);
  };
  std::vector<double> y;
  for (int n = 0; n < out[0]; ++n)
    for (int oy = 0; oy < out[1]; ++oy)
      for (int ox = 0; ox < out[2]; ++ox)
        for (int c = 0; c < out[3]; ++c) {
          const double sy = src(oy, in[1], out[1]), sx = src(ox, in[2], out[2]);
          const int y0 = static_cast<int>(sy), x0 = static_cast<int>(sx);
          const int y1 = std::min(y0 + 1, in[1] - 1), x1 = std::min(x0 + 1, in[2] - 1);
          auto at = [&](int iy, int ix) {
            return x[((static_cast<size_t>(n) * in[1] + iy) * in[2] + ix) * in[3] + c];
          };
          const double fy = sy - y0, fx = sx - x0;
          y.push_back((1 - fy) * ((1 - fx) * at(y0, x0) + fx * at(y0, x1)) +
                      fy * ((1 - fx) * at(y1, x0) + fx * at(y1, x1)));
        }
  return y;
}

TEST(ReferenceResizeBilinear, HandComputed) {
  const std::vector<float> x{0, 1, 2, 3};  // 2x2
  // align_corners: 2x2 -> 3x3 puts the corners on the input pixels.
  EXPECT_EQ(run1<float>(single_op(OpType::kResizeBilinear, DType::kFloat32, {1, 2, 2, 1},
                                  {1, 3, 3, 1}, ResizeBilinearParams{true}),
                        x),
            (std::vector<float>{0, 0.5f, 1, 1, 1.5f, 2, 2, 2.5f, 3}));
  // Half-pixel 2 -> 4 along x: sources -0.25 (clamped to 0), 0.25, 0.75, 1.25 -> 0, .25, .75, 1.
  EXPECT_EQ(run1<float>(single_op(OpType::kResizeBilinear, DType::kFloat32, {1, 1, 2, 1},
                                  {1, 1, 4, 1}, ResizeBilinearParams{false}),
                        std::vector<float>{0, 1}),
            (std::vector<float>{0, 0.25f, 0.75f, 1}));
}

TEST(ReferenceResizeBilinear, MatchesBruteForceFloat32AndInt8) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  struct Case {
    Dims in, out;
  };
  const Case cases[] = {{{1, 4, 5, 3}, {1, 8, 10, 3}},
                        {{2, 6, 6, 2}, {2, 3, 4, 2}},
                        {{1, 3, 7, 1}, {1, 5, 2, 1}},
                        {{1, 1, 1, 2}, {1, 3, 3, 2}}};
  for (const Case& c : cases) {
    for (bool align : {false, true}) {
      SCOPED_TRACE(::testing::Message() << "align_corners " << align);
      const auto xf = rng.floats(count(c.in), -3, 3);
      const auto yf = run1<float>(single_op(OpType::kResizeBilinear, DType::kFloat32, c.in, c.out,
                                            ResizeBilinearParams{align}),
                                  xf);
      const auto ef = resize_naive({xf.begin(), xf.end()}, c.in, c.out, align);
      ASSERT_EQ(yf.size(), ef.size());
      for (size_t i = 0; i < yf.size(); ++i) ASSERT_NEAR(yf[i], ef[i], kFloatTolerance) << i;

      const QParams q{0.05f, -4};
      const auto xq = rng.int8s(count(c.in));
      const auto yq = run1<int8_t>(single_op(OpType::kResizeBilinear, DType::kInt8, c.in, c.out,
                                             ResizeBilinearParams{align}, q, q),
                                   xq);
      std::vector<double> xr;
      for (int8_t v : xq) xr.push_back(q.real(v));
      std::vector<int8_t> expected;
      for (double v : resize_naive(xr, c.in, c.out, align))
        expected.push_back(quantize_double(v, q));
      expect_int8_near(yq, expected, kInt8Tolerance, "int8 resize");
    }
  }
}

// ---- Quantize / Dequantize ----

TEST(ReferenceConvert, QuantizeRoundsHalfToEvenAndSaturates) {
  const QParams q{0.5f, -10};
  // x / 0.5: 0.5 (tie -> 0), 1.5 (tie -> 2), -2.5 (tie -> -2), 3.3 -> 3; then + (-10); rails.
  const std::vector<float> x{0.25f, 0.75f, -1.25f, 1.65f, 1e9f, -1e9f, 68.5f, -59.0f};
  EXPECT_EQ(
      run1<int8_t>(single_op(OpType::kQuantize, DType::kFloat32, {8}, {8}, NoParams{}, {}, q), x),
      (std::vector<int8_t>{-10, -8, -12, -7, 127, -128, 127, -128}));
}

TEST(ReferenceConvert, DequantizeIsExact) {
  const QParams q{0.125f, 3};
  const std::vector<int8_t> x{-128, 0, 3, 127};
  EXPECT_EQ(
      run1<float>(single_op(OpType::kDequantize, DType::kInt8, {2, 2}, {2, 2}, NoParams{}, q), x),
      (std::vector<float>{-16.375f, -0.375f, 0, 15.5f}));
}

}  // namespace
}  // namespace tlvlink::reference_test
