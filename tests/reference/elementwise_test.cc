// Add / Mul (numpy broadcasting up to rank 6, fused activations), Clamp and Sigmoid, fp32 and
// int8. Broadcasting is checked against an independent unravel/ravel index computation.
#include <algorithm>
#include <cmath>
#include <limits>

#include "reference/ref_util.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::reference_test {
namespace {

// std::exp and the float division differ from the double formula by a few ulp; outputs are
// in (0, 1).
constexpr double kSigmoidTolerance = 1e-6;

using Dims = std::vector<int32_t>;

size_t count(const Dims& d) {
  size_t n = 1;
  for (int32_t v : d) n *= static_cast<size_t>(v);
  return n;
}

Dims broadcast_dims(const Dims& a, const Dims& b) {
  const size_t r = std::max(a.size(), b.size());
  Dims out(r);
  for (size_t i = 0; i < r; ++i) {
    const int32_t da = i < r - a.size() ? 1 : a[i - (r - a.size())];
    const int32_t db = i < r - b.size() ? 1 : b[i - (r - b.size())];
    out[i] = std::max(da, db);
  }
  return out;
}

// Index into an input of dims `in` for output multi-index `idx` (numpy rules, right-aligned).
size_t source_index(const Dims& in, const std::vector<int32_t>& idx) {
  size_t flat = 0;
  const size_t offset = idx.size() - in.size();
  for (size_t i = 0; i < in.size(); ++i) {
    flat =
        flat * static_cast<size_t>(in[i]) + (in[i] == 1 ? 0 : static_cast<size_t>(idx[offset + i]));
  }
  return flat;
}

// Calls f(out_flat, a_flat, b_flat) by unravelling every output index.
template <typename F>
void for_each_pair(const Dims& a, const Dims& b, F f) {
  const Dims out = broadcast_dims(a, b);
  std::vector<int32_t> idx(out.size());
  for (size_t o = 0; o < count(out); ++o) {
    size_t rem = o;
    for (size_t i = out.size(); i-- > 0;) {
      idx[i] = static_cast<int32_t>(rem % static_cast<size_t>(out[i]));
      rem /= static_cast<size_t>(out[i]);
    }
    f(o, source_index(a, idx), source_index(b, idx));
  }
}

std::vector<std::byte> binary_model(OpType type, DType dtype, const Dims& a, const Dims& b,
                                    Activation act, QParams qa = {}, QParams qb = {},
                                    QParams qy = {}) {
  const bool q = dtype == DType::kInt8;
  ModelBuilder m;
  const int32_t ta = m.add_activation("a", dtype, a, q ? qa.spec() : QuantSpec{});
  const int32_t tb = m.add_activation("b", dtype, b, q ? qb.spec() : QuantSpec{});
  const int32_t ty =
      m.add_activation("y", dtype, broadcast_dims(a, b), q ? qy.spec() : QuantSpec{});
  m.add_op(type, "binary", {ta, tb}, ty, BinaryParams{act});
  m.set_inputs({ta, tb});
  m.set_outputs({ty});
  return m.finish();
}

template <typename T>
std::vector<T> run2(const std::vector<std::byte>& file, const std::vector<T>& a,
                    const std::vector<T>& b) {
  auto out = run_reference(file, {to_bytes(a), to_bytes(b)});
  return out.empty() ? std::vector<T>() : from_bytes<T>(out[0]);
}

TEST(ReferenceBinary, HandComputedBroadcast) {
  const std::vector<float> a{1, 2, 3, 4, 5, 6};  // [2, 3]
  EXPECT_EQ(run2<float>(binary_model(OpType::kAdd, DType::kFloat32, {2, 3}, {3}, Activation::kNone),
                        a, {10, 20, 30}),
            (std::vector<float>{11, 22, 33, 14, 25, 36}));
  EXPECT_EQ(
      run2<float>(binary_model(OpType::kMul, DType::kFloat32, {2, 3}, {2, 1}, Activation::kNone), a,
                  {2, -3}),
      (std::vector<float>{2, 4, 6, -12, -15, -18}));
  // Both sides broadcast: [3, 1] + [1, 2] -> [3, 2], then ReLU6.
  EXPECT_EQ(
      run2<float>(binary_model(OpType::kAdd, DType::kFloat32, {3, 1}, {1, 2}, Activation::kRelu6),
                  {-5, 1, 4}, {0, 3}),
      (std::vector<float>{0, 0, 1, 4, 4, 6}));
}

struct ShapePair {
  Dims a, b;
};
const std::vector<ShapePair>& shape_pairs() {
  static const std::vector<ShapePair> pairs{{{2, 3, 4}, {2, 3, 4}},
                                            {{1, 4, 4, 8}, {8}},
                                            {{1, 4, 4, 8}, {1, 1, 1, 8}},
                                            {{2, 1, 3, 1, 2, 4}, {3, 5, 1, 4}},
                                            {{1, 5, 1, 2, 1, 3}, {2, 1, 1, 2, 4, 1}},
                                            {{1}, {3, 2, 2}},
                                            {{4, 1, 2}, {1, 3, 1}}};
  return pairs;
}

TEST(ReferenceBinary, Float32BroadcastMatchesIndependentIndexing) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  for (OpType type : {OpType::kAdd, OpType::kMul}) {
    for (Activation act : {Activation::kNone, Activation::kRelu, Activation::kRelu6}) {
      for (const ShapePair& p : shape_pairs()) {
        const auto a = rng.floats(count(p.a), -8, 8), b = rng.floats(count(p.b), -8, 8);
        const auto y = run2<float>(binary_model(type, DType::kFloat32, p.a, p.b, act), a, b);
        ASSERT_EQ(y.size(), count(broadcast_dims(p.a, p.b)));
        const float lo = activation_min(act), hi = activation_max(act);
        for_each_pair(p.a, p.b, [&](size_t o, size_t i, size_t j) {
          const float v = type == OpType::kAdd ? a[i] + b[j] : a[i] * b[j];
          // One float operation, then the clamp: the kernel must reproduce it bit for bit.
          ASSERT_EQ(y[o], std::min(std::max(v, lo), hi)) << "element " << o;
        });
      }
    }
  }
}

TEST(ReferenceBinary, Int8MatchesDequantizedFloatWithin1LsbAndHitsRails) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  Rng rng(seed);
  size_t exact = 0, total = 0;
  for (OpType type : {OpType::kAdd, OpType::kMul}) {
    for (Activation act : {Activation::kNone, Activation::kRelu, Activation::kRelu6}) {
      for (const ShapePair& p : shape_pairs()) {
        const QParams qa{rng.uniform(0.01f, 0.05f), rng.int_in(-20, 20)};
        const QParams qb{rng.uniform(0.01f, 0.05f), rng.int_in(-20, 20)};
        // Output range narrower than the inputs' so the rails are reached; the first output
        // is driven far positive and the last far negative (|a - zp|, |b - zp| >= 107 steps of
        // >= 0.01: sums beyond +/-2.1 and products beyond +/-1.1).
        const float range = type == OpType::kAdd ? 2.0f : 1.0f;
        const QParams qy{range / 255.0f, rng.int_in(-5, 5)};
        auto a = rng.int8s(count(p.a)), b = rng.int8s(count(p.b));
        a.front() = b.front() = 127;
        a.back() = type == OpType::kAdd ? -128 : 127;
        b.back() = -128;
        const auto y =
            run2<int8_t>(binary_model(type, DType::kInt8, p.a, p.b, act, qa, qb, qy), a, b);
        const int32_t lo = activation_qmin(act, qy), hi = activation_qmax(act, qy);
        std::vector<int8_t> expected(y.size());
        for_each_pair(p.a, p.b, [&](size_t o, size_t i, size_t j) {
          const double ra = qa.real(a[i]), rb = qb.real(b[j]);
          expected[o] = quantize_double(type == OpType::kAdd ? ra + rb : ra * rb, qy, lo, hi);
        });
        exact += expect_int8_near(y, expected, kInt8Tolerance, "int8 binary");
        total += y.size();
        if (a.size() > 1 && b.size() > 1) {  // else front and back are the same input element
          EXPECT_EQ(y.front(), hi);
          EXPECT_EQ(y.back(), lo);
        }
      }
    }
  }
  std::printf("[ figures ] int8 add/mul: %zu of %zu outputs equal the double oracle exactly\n",
              exact, total);
}

TEST(ReferenceBinary, Int8RailsExact) {
  // 100 * 0.1 + 100 * 0.1 = 20 on an output of scale 0.05 -> 400 -> 127; negated -> -128.
  const QParams q{0.1f, 0}, qy{0.05f, 0};
  EXPECT_EQ(
      run2<int8_t>(binary_model(OpType::kAdd, DType::kInt8, {4}, {4}, Activation::kNone, q, q, qy),
                   {100, -100, 1, -1}, {100, -100, 2, -3}),
      (std::vector<int8_t>{127, -128, 6, -8}));
  // (1.0 * 1.2) / 0.05 = 24; (10 * 10) -> 127; (-10 * 10) -> -128.
  EXPECT_EQ(
      run2<int8_t>(binary_model(OpType::kMul, DType::kInt8, {4}, {4}, Activation::kNone, q, q, qy),
                   {10, 100, -100, 0}, {12, 100, 100, 5}),
      (std::vector<int8_t>{24, 127, -128, 0}));
}

std::vector<std::byte> unary_model(OpType type, DType dtype, const Dims& shape, OpParams params,
                                   QParams qx = {}, QParams qy = {}) {
  const bool q = dtype == DType::kInt8;
  ModelBuilder m;
  const int32_t x = m.add_activation("x", dtype, shape, q ? qx.spec() : QuantSpec{});
  const int32_t y = m.add_activation("y", dtype, shape, q ? qy.spec() : QuantSpec{});
  m.add_op(type, "unary", {x}, y, params);
  m.set_inputs({x});
  m.set_outputs({y});
  return m.finish();
}

TEST(ReferenceClamp, Float32AndInt8) {
  const std::vector<float> x{-3, -1, -0.5f, 0, 1.25f, 2.5f, 7};
  EXPECT_EQ(
      run1<float>(unary_model(OpType::kClamp, DType::kFloat32, {7}, ClampParams{-1, 2.5f}), x),
      (std::vector<float>{-1, -1, -0.5f, 0, 1.25f, 2.5f, 2.5f}));
  // int8 with scale 0.1, zero point 3: bounds round(-1/0.1)+3 = -7 and round(2.5/0.1)+3 = 28.
  const QParams q{0.1f, 3};
  const std::vector<int8_t> xq{-128, -8, -7, 0, 27, 28, 29, 127};
  EXPECT_EQ(
      run1<int8_t>(unary_model(OpType::kClamp, DType::kInt8, {8}, ClampParams{-1, 2.5f}, q, q), xq),
      (std::vector<int8_t>{-7, -7, -7, 0, 27, 28, 28, 28}));
  // An unbounded side does not clamp.
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(
      run1<int8_t>(unary_model(OpType::kClamp, DType::kInt8, {8}, ClampParams{0, inf}, q, q), xq),
      (std::vector<int8_t>{3, 3, 3, 3, 27, 28, 29, 127}));
}

TEST(ReferenceSigmoid, Float32MatchesFormula) {
  std::vector<float> x;
  for (int i = -100; i <= 100; ++i) x.push_back(static_cast<float>(i) * 0.25f);
  x.push_back(-200.0f);  // exp overflows to inf: result 0, not NaN
  x.push_back(200.0f);
  const auto y = run1<float>(
      unary_model(OpType::kSigmoid, DType::kFloat32, {static_cast<int32_t>(x.size())}, NoParams{}),
      x);
  ASSERT_EQ(y.size(), x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    EXPECT_NEAR(y[i], 1.0 / (1.0 + std::exp(-static_cast<double>(x[i]))), kSigmoidTolerance)
        << x[i];
  }
}

TEST(ReferenceSigmoid, Int8AllInputsWithin1LsbAndRails) {
  const QParams qx{0.08f, 5}, qy{1.0f / 256, -128};
  std::vector<int8_t> x;
  for (int v = -128; v <= 127; ++v) x.push_back(static_cast<int8_t>(v));
  const auto y =
      run1<int8_t>(unary_model(OpType::kSigmoid, DType::kInt8, {256}, NoParams{}, qx, qy), x);
  std::vector<int8_t> expected;
  for (int8_t v : x) expected.push_back(quantize_double(1.0 / (1.0 + std::exp(-qx.real(v))), qy));
  const size_t exact = expect_int8_near(y, expected, kInt8Tolerance, "int8 sigmoid");
  EXPECT_EQ(y.front(), -128);  // sigmoid(-10.64) * 256 = 0.006 -> 0 - 128
  EXPECT_EQ(y.back(), 127);    // sigmoid(9.76) * 256 = 255.99 -> 256 - 128, saturated
  std::printf("[ figures ] int8 sigmoid: %zu of 256 inputs equal the double oracle exactly\n",
              exact);
}

}  // namespace
}  // namespace tlvlink::reference_test
