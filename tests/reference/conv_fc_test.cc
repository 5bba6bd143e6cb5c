// Conv2D and FullyConnected: hand-computed cases, brute-force float loops written independently
// here (explicitly padded input, different loop order, double accumulation), the int8 oracle
// (dequantize -> float conv -> quantize) within 1 LSB, fused activations, both rails, and the
// int32 accumulator at its worst-case bound.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "reference/ref_util.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::reference_test {
namespace {

// float32 epsilon (1.2e-7) times the reduction length (<= 200 here) stays below 1e-5 of
// sum|x*w| + |b|; an indexing mistake gives O(1) relative errors.
constexpr double kFloatRelTolerance = 1e-5;

struct ConvSpec {
  int n = 1, h = 5, w = 5, cin = 3, cout = 4, kh = 3, kw = 3;
  int sh = 1, sw = 1, dh = 1, dw = 1, pt = 0, pb = 0, pl = 0, pr = 0, groups = 1;
  Activation act = Activation::kNone;
  bool bias = true;

  int oh() const { return (h + pt + pb - ((kh - 1) * dh + 1)) / sh + 1; }
  int ow() const { return (w + pl + pr - ((kw - 1) * dw + 1)) / sw + 1; }
  Conv2DParams params() const { return {kh, kw, sh, sw, dh, dw, pt, pb, pl, pr, groups, act}; }
  size_t in_size() const { return static_cast<size_t>(n) * h * w * cin; }
  size_t w_size() const { return static_cast<size_t>(cout) * kh * kw * (cin / groups); }
  size_t out_size() const { return static_cast<size_t>(n) * oh() * ow() * cout; }
};

struct Naive {
  std::vector<double> y, magnitude;  // magnitude: sum |x*w| + |b| per output (error bound)
};

// Independent conv: copy into an explicitly zero-padded NHWC buffer, iterate n, oc, oy, ox.
Naive conv_naive(const ConvSpec& s, const std::vector<double>& x, const std::vector<double>& w,
                 const std::vector<double>& b) {
  const int ph = s.h + s.pt + s.pb, pw = s.w + s.pl + s.pr;
  std::vector<double> padded(static_cast<size_t>(s.n) * ph * pw * s.cin, 0.0);
  auto pidx = [&](int n, int y, int x_, int c) {
    return ((static_cast<size_t>(n) * ph + y) * pw + x_) * s.cin + c;
  };
  for (int n = 0; n < s.n; ++n)
    for (int y = 0; y < s.h; ++y)
      for (int x_ = 0; x_ < s.w; ++x_)
        for (int c = 0; c < s.cin; ++c)
          padded[pidx(n, y + s.pt, x_ + s.pl, c)] =
              x[((static_cast<size_t>(n) * s.h + y) * s.w + x_) * s.cin + c];
  const int cin_g = s.cin / s.groups, cout_g = s.cout / s.groups;
  Naive r;
  r.y.assign(s.out_size(), 0.0);
  r.magnitude.assign(s.out_size(), 0.0);
  for (int n = 0; n < s.n; ++n) {
    for (int oc = 0; oc < s.cout; ++oc) {
      const int group = oc / cout_g;
      for (int oy = 0; oy < s.oh(); ++oy) {
        for (int ox = 0; ox < s.ow(); ++ox) {
          double sum = s.bias ? b[oc] : 0.0, mag = s.bias ? std::fabs(b[oc]) : 0.0;
          for (int ic = 0; ic < cin_g; ++ic) {
            for (int ky = 0; ky < s.kh; ++ky) {
              for (int kx = 0; kx < s.kw; ++kx) {
                const double xv = padded[pidx(n, oy * s.sh + ky * s.dh, ox * s.sw + kx * s.dw,
                                              group * cin_g + ic)];
                const double wv =
                    w[((static_cast<size_t>(oc) * s.kh + ky) * s.kw + kx) * cin_g + ic];
                sum += xv * wv;
                mag += std::fabs(xv * wv);
              }
            }
          }
          const size_t o = ((static_cast<size_t>(n) * s.oh() + oy) * s.ow() + ox) * s.cout + oc;
          r.y[o] = sum;
          r.magnitude[o] = mag;
        }
      }
    }
  }
  return r;
}

double apply_activation(double v, Activation a) {
  if (a == Activation::kNone) return v;
  v = std::max(v, 0.0);
  return a == Activation::kRelu6 ? std::min(v, 6.0) : v;
}

std::vector<std::byte> conv_model_f32(const ConvSpec& s, const std::vector<float>& w,
                                      const std::vector<float>& b) {
  ModelBuilder m;
  const int32_t x = m.add_activation("x", DType::kFloat32, {s.n, s.h, s.w, s.cin});
  const int32_t wt =
      m.add_constant<float>("w", {s.cout, s.kh, s.kw, s.cin / s.groups}, std::span<const float>(w));
  const int32_t bt =
      s.bias ? m.add_constant<float>("b", {s.cout}, std::span<const float>(b)) : kNoTensor;
  const int32_t y = m.add_activation("y", DType::kFloat32, {s.n, s.oh(), s.ow(), s.cout});
  m.add_op(OpType::kConv2D, "conv", {x, wt, bt}, y, s.params());
  m.set_inputs({x});
  m.set_outputs({y});
  return m.finish();
}

struct Int8Conv {
  QParams in, out;
  std::vector<int8_t> w;
  std::vector<float> w_scales;
  std::vector<int32_t> bias;
};

std::vector<std::byte> conv_model_qs8(const ConvSpec& s, const Int8Conv& q) {
  ModelBuilder m;
  const int32_t x = m.add_activation("x", DType::kInt8, {s.n, s.h, s.w, s.cin}, q.in.spec());
  const QuantSpec wq = q.w_scales.size() == 1 ? QuantSpec::per_tensor(q.w_scales[0], 0)
                                              : QuantSpec::per_channel(q.w_scales, 0);
  const int32_t wt = m.add_constant<int8_t>("w", {s.cout, s.kh, s.kw, s.cin / s.groups},
                                            std::span<const int8_t>(q.w), wq);
  int32_t bt = kNoTensor;
  if (s.bias) {
    std::vector<float> bs;
    for (float sw : q.w_scales) bs.push_back(q.in.scale * sw);
    const QuantSpec bq =
        bs.size() == 1 ? QuantSpec::per_tensor(bs[0], 0) : QuantSpec::per_channel(bs, 0);
    bt = m.add_constant<int32_t>("b", {s.cout}, std::span<const int32_t>(q.bias), bq);
  }
  const int32_t y =
      m.add_activation("y", DType::kInt8, {s.n, s.oh(), s.ow(), s.cout}, q.out.spec());
  m.add_op(OpType::kConv2D, "conv", {x, wt, bt}, y, s.params());
  m.set_inputs({x});
  m.set_outputs({y});
  return m.finish();
}

TEST(ReferenceConv, HandComputed2x2Valid) {
  ConvSpec s;
  s.h = s.w = 3;
  s.cin = s.cout = 1;
  s.kh = s.kw = 2;
  const std::vector<float> x{1, 2, 3, 4, 5, 6, 7, 8, 9};
  const auto y = run1<float>(conv_model_f32(s, {1, 2, 3, 4}, {0.5f}), x);
  // y(0,0) = 1*1 + 2*2 + 3*4 + 4*5 + 0.5, and so on.
  EXPECT_EQ(y, (std::vector<float>{37.5f, 47.5f, 67.5f, 77.5f}));
}

TEST(ReferenceConv, HandComputedPaddedAndStrided) {
  ConvSpec s;
  s.h = s.w = 3;
  s.cin = s.cout = 1;
  s.pt = s.pb = s.pl = s.pr = 1;
  s.bias = false;
  const std::vector<float> x{1, 2, 3, 4, 5, 6, 7, 8, 9}, ones(9, 1.0f);
  // 3x3 box sums with zero padding.
  EXPECT_EQ(run1<float>(conv_model_f32(s, ones, {}), x),
            (std::vector<float>{12, 21, 16, 27, 45, 33, 24, 39, 28}));
  s.sh = s.sw = 2;
  EXPECT_EQ(run1<float>(conv_model_f32(s, ones, {}), x), (std::vector<float>{12, 16, 24, 28}));
}

TEST(ReferenceConv, HandComputedDepthwiseMultiplier) {
  // Depthwise, 2 input channels, multiplier 2: output channel oc reads input channel oc / 2.
  ConvSpec s;
  s.h = s.w = 1;
  s.kh = s.kw = 1;
  s.cin = 2;
  s.cout = 4;
  s.groups = 2;
  s.bias = false;
  EXPECT_EQ(run1<float>(conv_model_f32(s, {1, 10, 100, 1000}, {}), std::vector<float>{3, 5}),
            (std::vector<float>{3, 30, 500, 5000}));
}

struct NamedSpec {
  const char* name;
  ConvSpec spec;
};

std::vector<NamedSpec> conv_cases() {
  std::vector<NamedSpec> cases;
  ConvSpec s;
  cases.push_back({"plain", s});
  s.bias = false;
  cases.push_back({"no_bias", s});
  s = ConvSpec{};
  s.cin = 4, s.cout = 6, s.groups = 2;
  cases.push_back({"grouped", s});
  s = ConvSpec{};
  s.cin = 3, s.cout = 6, s.groups = 3, s.pt = s.pb = s.pl = s.pr = 1;
  cases.push_back({"depthwise_x2_padded", s});
  s = ConvSpec{};
  s.h = 9, s.w = 8, s.sh = 2, s.sw = 3;
  cases.push_back({"strided", s});
  s = ConvSpec{};
  s.h = s.w = 9, s.dh = 2, s.dw = 3;
  cases.push_back({"dilated", s});
  s = ConvSpec{};
  s.n = 2, s.pt = 1, s.pb = 2, s.pl = 0, s.pr = 1, s.sh = 2, s.act = Activation::kRelu;
  cases.push_back({"batch2_asym_pad_relu", s});
  s = ConvSpec{};
  s.h = s.w = 6, s.cin = 8, s.cout = 8, s.groups = 8, s.kh = s.kw = 3, s.sh = s.sw = 2,
  s.pt = s.pl = 1, s.dh = 2, s.act = Activation::kRelu6;
  cases.push_back({"depthwise_strided_dilated_relu6", s});
  s = ConvSpec{};
  s.kh = 1, s.kw = 3, s.cin = 6, s.cout = 4, s.groups = 2, s.pl = s.pr = 2, s.dw = 2;
  cases.push_back({"grouped_1x3_dilated_padded", s});
  return cases;
}

TEST(ReferenceConv, Float32MatchesBruteForce) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  for (const NamedSpec& c : conv_cases()) {
    SCOPED_TRACE(c.name);
    const ConvSpec& s = c.spec;
    const auto x = rng.floats(s.in_size(), -2, 2);
    const auto w = rng.floats(s.w_size(), -1, 1);
    const auto b = rng.floats(static_cast<size_t>(s.cout), -1, 1);
    const auto y = run1<float>(conv_model_f32(s, w, b), x);
    const Naive ref =
        conv_naive(s, {x.begin(), x.end()}, {w.begin(), w.end()}, {b.begin(), b.end()});
    ASSERT_EQ(y.size(), ref.y.size());
    for (size_t i = 0; i < y.size(); ++i) {
      ASSERT_NEAR(y[i], apply_activation(ref.y[i], s.act), kFloatRelTolerance * ref.magnitude[i])
          << "element " << i;
    }
  }
}

// Random int8 conv; output scale from the float range times `range_factor` (< 1 saturates).
void check_int8_conv(const ConvSpec& s, bool per_channel, float range_factor, Rng& rng,
                     size_t& exact, size_t& total, bool& hit_low, bool& hit_high) {
  Int8Conv q;
  q.in = {0.02f, rng.int_in(-20, 20)};
  const auto x = rng.int8s(s.in_size());
  q.w = rng.int8s(s.w_size(), -127, 127);
  for (int c = 0; c < (per_channel ? s.cout : 1); ++c)
    q.w_scales.push_back(rng.uniform(0.002f, 0.02f));
  for (int c = 0; c < s.cout; ++c) q.bias.push_back(rng.int_in(-2000, 2000));

  // Real-valued conv of the dequantized tensors.
  auto w_scale = [&](size_t c) { return static_cast<double>(q.w_scales[per_channel ? c : 0]); };
  std::vector<double> xr(x.size()), wr(q.w.size()), br(q.bias.size());
  for (size_t i = 0; i < x.size(); ++i) xr[i] = q.in.real(x[i]);
  const size_t per = s.w_size() / static_cast<size_t>(s.cout);
  for (size_t i = 0; i < wr.size(); ++i) wr[i] = q.w[i] * w_scale(i / per);
  for (size_t c = 0; c < br.size(); ++c)
    br[c] = q.bias[c] * static_cast<double>(q.in.scale) * w_scale(c);
  const Naive ref = conv_naive(s, xr, wr, br);
  double max_abs = 1e-3;
  for (double v : ref.y) max_abs = std::max(max_abs, std::fabs(v));
  q.out = {static_cast<float>(max_abs * static_cast<double>(range_factor) / 127.0),
           rng.int_in(-10, 10)};

  const auto y = run1<int8_t>(conv_model_qs8(s, q), x);
  const int32_t lo = activation_qmin(s.act, q.out), hi = activation_qmax(s.act, q.out);
  std::vector<int8_t> expected(ref.y.size());
  for (size_t i = 0; i < expected.size(); ++i)
    expected[i] = quantize_double(ref.y[i], q.out, lo, hi);
  exact += expect_int8_near(y, expected, kInt8Tolerance, "int8 conv");
  total += expected.size();
  hit_low = hit_low || contains(y, static_cast<int8_t>(lo));
  hit_high = hit_high || contains(y, static_cast<int8_t>(hi));
}

TEST(ReferenceConv, Int8MatchesDequantizedFloatWithin1Lsb) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  size_t exact = 0, total = 0;
  bool low = false, high = false;
  for (const NamedSpec& c : conv_cases()) {
    SCOPED_TRACE(c.name);
    for (bool per_channel : {true, false}) {
      check_int8_conv(c.spec, per_channel, 0.6f, rng, exact, total, low, high);
    }
  }
  EXPECT_TRUE(low && high) << "range factor 0.6 should drive outputs to both rails";
  std::printf("[ figures ] int8 conv: %zu of %zu outputs equal the double oracle exactly\n", exact,
              total);
}

// ---- FullyConnected ----

std::vector<std::byte> fc_model_f32(int n, int cin, int cout, const std::vector<float>& w,
                                    const std::vector<float>* b, Activation act) {
  ModelBuilder m;
  const int32_t x = m.add_activation("x", DType::kFloat32, {n, cin});
  const int32_t wt = m.add_constant<float>("w", {cout, cin}, std::span<const float>(w));
  const int32_t bt = b ? m.add_constant<float>("b", {cout}, std::span<const float>(*b)) : kNoTensor;
  const int32_t y = m.add_activation("y", DType::kFloat32, {n, cout});
  m.add_op(OpType::kFullyConnected, "fc", {x, wt, bt}, y, FullyConnectedParams{act});
  m.set_inputs({x});
  m.set_outputs({y});
  return m.finish();
}

std::vector<std::byte> fc_model_qs8(int n, int cin, int cout, const Int8Conv& q, Activation act) {
  ModelBuilder m;
  const int32_t x = m.add_activation("x", DType::kInt8, {n, cin}, q.in.spec());
  const QuantSpec wq = q.w_scales.size() == 1 ? QuantSpec::per_tensor(q.w_scales[0], 0)
                                              : QuantSpec::per_channel(q.w_scales, 0);
  const int32_t wt = m.add_constant<int8_t>("w", {cout, cin}, std::span<const int8_t>(q.w), wq);
  std::vector<float> bs;
  for (float sw : q.w_scales) bs.push_back(q.in.scale * sw);
  const QuantSpec bq =
      bs.size() == 1 ? QuantSpec::per_tensor(bs[0], 0) : QuantSpec::per_channel(bs, 0);
  const int32_t bt =
      q.bias.empty() ? kNoTensor
                     : m.add_constant<int32_t>("b", {cout}, std::span<const int32_t>(q.bias), bq);
  const int32_t y = m.add_activation("y", DType::kInt8, {n, cout}, q.out.spec());
  m.add_op(OpType::kFullyConnected, "fc", {x, wt, bt}, y, FullyConnectedParams{act});
  m.set_inputs({x});
  m.set_outputs({y});
  return m.finish();
}

TEST(ReferenceFullyConnected, HandComputedWithActivations) {
  const std::vector<float> w{1, 2, 3, -1, -2, -3, 0.5f, 0.5f, 4};  // [3, 3]
  const std::vector<float> b{0.5f, 0, -1};
  const std::vector<float> x{1, 1, 2, 2, 0, 1};  // [2, 3]
  // Row 0: 1+2+6+0.5 = 9.5, -9, 0.5+0.5+8-1 = 8; row 1: 2+3+0.5 = 5.5, -5, 1+4-1 = 4.
  EXPECT_EQ(run1<float>(fc_model_f32(2, 3, 3, w, &b, Activation::kNone), x),
            (std::vector<float>{9.5f, -9, 8, 5.5f, -5, 4}));
  EXPECT_EQ(run1<float>(fc_model_f32(2, 3, 3, w, &b, Activation::kRelu), x),
            (std::vector<float>{9.5f, 0, 8, 5.5f, 0, 4}));
  EXPECT_EQ(run1<float>(fc_model_f32(2, 3, 3, w, nullptr, Activation::kRelu6), x),
            (std::vector<float>{6, 0, 6, 5, 0, 5}));
}

TEST(ReferenceFullyConnected, Int8MatchesDequantizedFloatWithin1Lsb) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  const int n = 3, cin = 40, cout = 7;
  for (Activation act : {Activation::kNone, Activation::kRelu, Activation::kRelu6}) {
    for (bool per_channel : {true, false}) {
      SCOPED_TRACE(::testing::Message()
                   << "activation " << static_cast<int>(act) << " per_channel " << per_channel);
      Int8Conv q;
      q.in = {0.03f, rng.int_in(-128, 127)};
      const auto x = rng.int8s(static_cast<size_t>(n) * cin);
      q.w = rng.int8s(static_cast<size_t>(cout) * cin, -127, 127);
      for (int c = 0; c < (per_channel ? cout : 1); ++c)
        q.w_scales.push_back(rng.uniform(0.001f, 0.01f));
      for (int c = 0; c < cout; ++c) q.bias.push_back(rng.int_in(-5000, 5000));
      q.out = {0.02f, rng.int_in(-30, 30)};
      const auto y = run1<int8_t>(fc_model_qs8(n, cin, cout, q, act), x);
      std::vector<int8_t> expected;
      const int32_t lo = activation_qmin(act, q.out), hi = activation_qmax(act, q.out);
      for (int r = 0; r < n; ++r) {
        for (int c = 0; c < cout; ++c) {
          const auto sw = static_cast<double>(q.w_scales[per_channel ? static_cast<size_t>(c) : 0]);
          double real = q.bias[static_cast<size_t>(c)] * static_cast<double>(q.in.scale) * sw;
          for (int i = 0; i < cin; ++i) {
            real += q.in.real(x[static_cast<size_t>(r) * cin + i]) *
                    (q.w[static_cast<size_t>(c) * cin + i] * sw);
          }
          expected.push_back(quantize_double(real, q.out, lo, hi));
        }
      }
      expect_int8_near(y, expected, kInt8Tolerance, "int8 fc");
    }
  }
}

TEST(ReferenceFullyConnected, Int8SaturatesExactlyAtBothRailsAndActivationBounds) {
  // Input 127 with zero point -128 (centred 255); channel 0 weights +127, channel 1 -127,
  // channel 2 +1: accumulators +/-129540 and +1020, times 0.05*0.01/0.05 = 0.01 -> +/-1295.4, 10.2.
  const int cin = 4, cout = 3;
  Int8Conv q;
  q.in = {0.05f, -128};
  q.w = {127, 127, 127, 127, -127, -127, -127, -127, 1, 1, 1, 1};
  q.w_scales = {0.01f};
  q.out = {0.05f, 10};
  const std::vector<int8_t> x(cin, 127);
  EXPECT_EQ(run1<int8_t>(fc_model_qs8(1, cin, cout, q, Activation::kNone), x),
            (std::vector<int8_t>{127, -128, 20}));
  // ReLU: the lower bound is the zero point (real 0).
  EXPECT_EQ(run1<int8_t>(fc_model_qs8(1, cin, cout, q, Activation::kRelu), x),
            (std::vector<int8_t>{127, 10, 20}));
  // ReLU6 with s_y = 0.1: upper bound round(6 / 0.1) + 10 = 70; channel 2: 5.1 -> 5 + 10.
  q.out = {0.1f, 10};
  EXPECT_EQ(run1<int8_t>(fc_model_qs8(1, cin, cout, q, Activation::kRelu6), x),
            (std::vector<int8_t>{70, 10, 15}));
}

TEST(ReferenceFullyConnected, AccumulatorAtWorstCaseBoundIsExactOnBothExecutors) {
  // |bias| + 255 * 127 * K = 10,000,000 + 2,137,410,000 = 2,147,410,000 < 2^31 - 1: the largest
  // accumulator the loader admits at this K. An int32 overflow would flip the sign.
  const int cin = 66000, cout = 2;
  Int8Conv q;
  q.in = {1.0f / 64, -128};
  q.w.assign(static_cast<size_t>(cout) * cin, 127);
  std::fill(q.w.begin() + cin, q.w.end(), -127);
  q.w_scales = {1.0f / 128};
  q.bias = {10'000'000, -10'000'000};
  // multiplier s_x*s_w/s_y = 2^-13 / s_y; s_y chosen so the result is ~+/-100.3 (not a tie).
  q.out = {0x1p-13f * 2147410000.0f / 100.3f, 0};
  const std::vector<int8_t> x(cin, 127);
  const double multiplier = 0x1p-13 / static_cast<double>(q.out.scale);
  const int64_t acc = 10'000'000 + int64_t{255} * 127 * cin;
  const auto expected = static_cast<int8_t>(std::nearbyint(static_cast<double>(acc) * multiplier));
  EXPECT_EQ(expected, 100);
  // Both executors: XNNPACK runs this FC as a 1x1 convolution (its 2022 qs8 FC is missing).
  for (ExecutorKind kind : kAllExecutors) {
    SCOPED_TRACE(executor_kind_name(kind));
    EXPECT_EQ(run1<int8_t>(fc_model_qs8(1, cin, cout, q, Activation::kNone), x, kind),
              (std::vector<int8_t>{expected, static_cast<int8_t>(-expected)}));
  }
}

TEST(ReferenceConv, AccumulatorAtWorstCaseBoundIsExactOnBothExecutors) {
  // Same bound through the conv kernel: 1x1 conv with Cin = 66000 on a 1x1 image.
  ConvSpec s;
  s.h = s.w = 1, s.kh = s.kw = 1, s.cin = 66000, s.cout = 2;
  Int8Conv q;
  q.in = {1.0f / 64, -128};
  q.w.assign(s.w_size(), 127);
  std::fill(q.w.begin() + s.cin, q.w.end(), -127);
  q.w_scales = {1.0f / 128, 1.0f / 128};
  q.bias = {10'000'000, -10'000'000};
  q.out = {0x1p-13f * 2147410000.0f / 100.3f, 0};
  for (ExecutorKind kind : kAllExecutors) {
    SCOPED_TRACE(executor_kind_name(kind));
    EXPECT_EQ(run1<int8_t>(conv_model_qs8(s, q), std::vector<int8_t>(s.in_size(), 127), kind),
              (std::vector<int8_t>{100, -100}));
  }
}

}  // namespace
}  // namespace tlvlink::reference_test
