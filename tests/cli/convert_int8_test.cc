// The minimal post-training converter: activation parameters, pass-through sharing, weight and
// bias quantization, and error cases.

#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "support/random.h"
#include "support/test_models.h"
#include "tlvlink/executor.h"
#include "tlvlink/quant_math.h"
#include "tlvlink/quantize/calibrate.h"

namespace tlvlink {
namespace {

using quantize::activation_quant;
using quantize::ModelBuilder;
using quantize::QuantSpec;

TEST(ActivationQuant, RangeAlwaysIncludesZeroAndIsFloored) {
  // Positive-only range: zero maps exactly onto -128.
  QuantSpec q = activation_quant(0.5f, 6.0f);
  EXPECT_FLOAT_EQ(q.scale[0], 6.0f / 255.0f);
  EXPECT_EQ(q.zero_point[0], -128);
  // Negative-only range: zero maps onto 127.
  q = activation_quant(-3.0f, -1.0f);
  EXPECT_EQ(q.zero_point[0], 127);
  // Symmetric-ish range: zero point near the middle and 0.0 representable exactly.
  q = activation_quant(-1.0f, 1.0f);
  EXPECT_FLOAT_EQ(dequantize_value(q.zero_point[0], q.scale[0], q.zero_point[0]), 0.0f);
  // Zero range (dead tensor): floored to 2^-12, still a normal positive scale.
  q = activation_quant(0.0f, 0.0f);
  EXPECT_FLOAT_EQ(q.scale[0], quantize::kMinActivationRange / 255.0f);
  EXPECT_TRUE(std::isnormal(q.scale[0]));
}

// input -> conv(relu6) -> pad -> maxpool -> add(const) -> clamp -> sigmoid -> reshape -> fc -> out
std::vector<std::byte> small_float_model(testing::Rng& rng) {
  ModelBuilder b;
  const int32_t x = b.add_activation("x", DType::kFloat32, {1, 6, 6, 3});
  const std::vector<float> w = rng.floats(4 * 3 * 3 * 3, -0.5f, 0.5f),
                           bias = rng.floats(4, -0.1f, 0.1f);
  const int32_t wt = b.add_constant<float>("conv.w", {4, 3, 3, 3}, w);
  const int32_t bt = b.add_constant<float>("conv.b", {4}, bias);
  const int32_t c = b.add_activation("conv", DType::kFloat32, {1, 6, 6, 4});
  Conv2DParams cp;
  cp.kernel_h = cp.kernel_w = 3;
  cp.pad_top = cp.pad_bottom = cp.pad_left = cp.pad_right = 1;
  cp.activation = Activation::kRelu6;
  b.add_op(OpType::kConv2D, "conv", {x, wt, bt}, c, cp);
  const int32_t p = b.add_activation("pad", DType::kFloat32, {1, 8, 8, 4});
  PadParams pp;
  pp.before = {0, 1, 1, 0};
  pp.after = {0, 1, 1, 0};
  b.add_op(OpType::kPad, "pad", {c}, p, pp);
  const int32_t m = b.add_activation("pool", DType::kFloat32, {1, 4, 4, 4});
  Pool2DParams mp;
  mp.pool_h = mp.pool_w = mp.stride_h = mp.stride_w = 2;
  b.add_op(OpType::kMaxPool2D, "pool", {p}, m, mp);
  const std::vector<float> k = {0.5f, -1.0f, 0.25f, 2.0f};
  const int32_t kt = b.add_constant<float>("offset", {4}, k);
  const int32_t a = b.add_activation("add", DType::kFloat32, {1, 4, 4, 4});
  b.add_op(OpType::kAdd, "add", {m, kt}, a, BinaryParams{});
  const int32_t cl = b.add_activation("clamp", DType::kFloat32, {1, 4, 4, 4});
  b.add_op(OpType::kClamp, "clamp", {a}, cl, ClampParams{-1.0f, 4.0f});
  const int32_t s = b.add_activation("sigmoid", DType::kFloat32, {1, 4, 4, 4});
  b.add_op(OpType::kSigmoid, "sigmoid", {cl}, s);
  const int32_t r = b.add_activation("flat", DType::kFloat32, {1, 64});
  b.add_op(OpType::kReshape, "flat", {s}, r);
  const std::vector<float> fw = rng.floats(5 * 64, -0.2f, 0.2f);
  const int32_t fwt = b.add_constant<float>("fc.w", {5, 64}, fw);
  const int32_t out = b.add_activation("out", DType::kFloat32, {1, 5});
  b.add_op(OpType::kFullyConnected, "fc", {r, fwt, kNoTensor}, out, FullyConnectedParams{});
  b.set_inputs({x});
  b.set_outputs({out});
  b.metadata().name = "small";
  return b.finish();
}

TEST(ConvertInt8, SmallGraphSharesPassThroughParamsAndQuantizesWeights) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  auto fp32 = testing::load_model(small_float_model(rng));
  ASSERT_NE(fp32, nullptr);
  std::vector<std::vector<float>> inputs;
  for (int i = 0; i < 4; ++i) inputs.push_back(rng.floats(6 * 6 * 3, -2.0f, 2.0f));
  auto ranges = quantize::collect_ranges(*fp32, inputs);
  ASSERT_TRUE(ranges.ok()) << ranges.error().message();
  auto builder = quantize::convert_to_int8(*fp32, *ranges);
  ASSERT_TRUE(builder.ok()) << builder.error().message();
  auto q = testing::load_model(builder->finish());
  ASSERT_NE(q, nullptr);
  const Graph& g = q->graph();
  auto find = [&](std::string_view name) -> const Operator& {
    for (const Operator& op : g.operators)
      if (op.name == name) return op;
    ADD_FAILURE() << "no operator " << name;
    return g.operators.front();
  };
  auto same = [&](const Operator& op) {
    const Tensor& in = g.tensor(op.inputs[0]);
    const Tensor& out = g.tensor(op.output);
    return in.quant.scale[0] == out.quant.scale[0] &&
           in.quant.zero_point[0] == out.quant.zero_point[0];
  };
  for (const char* pass : {"pad", "pool", "clamp", "flat"}) EXPECT_TRUE(same(find(pass))) << pass;
  const Tensor& sig = g.tensor(find("sigmoid").output);
  EXPECT_EQ(sig.quant.scale[0], 1.0f / 256.0f);
  EXPECT_EQ(sig.quant.zero_point[0], -128);
  // ReLU6 conv output: range [0, <=6] so zero sits on the bottom rail.
  EXPECT_EQ(g.tensor(find("conv").output).quant.zero_point[0], -128);
  // Weights: per-channel symmetric, the largest magnitude of each channel maps to +-127.
  const Tensor& w = g.tensor(find("conv").inputs[1]);
  const auto* wq = reinterpret_cast<const int8_t*>(w.data.data());
  for (int32_t c = 0; c < 4; ++c) {
    int peak = 0;
    for (int i = 0; i < 27; ++i) peak = std::max(peak, std::abs(static_cast<int>(wq[c * 27 + i])));
    EXPECT_EQ(peak, 127) << "channel " << c;
  }
  const Tensor& bias = g.tensor(find("conv").inputs[2]);
  EXPECT_EQ(bias.dtype, DType::kInt32);
  EXPECT_NEAR(bias.quant.scale[1],
              g.tensor(find("conv").inputs[0]).quant.scale[0] * w.quant.scale[1], 1e-12);

  // The int8 model tracks the float one within a few output LSBs on a calibration input.
  auto ef = make_reference_executor(*fp32);
  auto eq = make_reference_executor(*q);
  ASSERT_TRUE(ef.ok() && eq.ok());
  std::memcpy((*ef)->input(0).data(), inputs[0].data(), inputs[0].size() * sizeof(float));
  std::memcpy((*eq)->input(0).data(), inputs[0].data(), inputs[0].size() * sizeof(float));
  ASSERT_TRUE((*ef)->invoke().ok());
  ASSERT_TRUE((*eq)->invoke().ok());
  const float out_scale = g.tensor(g.operators.back().inputs[0]).quant.scale[0];
  const auto* yf = reinterpret_cast<const float*>((*ef)->output(0).data());
  const auto* yq = reinterpret_cast<const float*>((*eq)->output(0).data());
  // Errors from ~6 quantized layers add up; 6 output LSBs bounds them on this small graph.
  constexpr float kMaxLsbError = 6.0f;
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(yq[i], yf[i], kMaxLsbError * out_scale) << i;
}

TEST(ConvertInt8, RejectsMissingRangesAndQuantizedModels) {
  testing::Rng rng(1);
  auto fp32 = testing::load_model(small_float_model(rng));
  ASSERT_NE(fp32, nullptr);
  std::vector<quantize::TensorRange> none(fp32->graph().tensors.size());
  auto r = quantize::convert_to_int8(*fp32, none);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(std::string(r.error().message()).find("calibration range"), std::string::npos);
  auto wrong_size = quantize::convert_to_int8(*fp32, std::vector<quantize::TensorRange>(3));
  EXPECT_FALSE(wrong_size.ok());

  ModelBuilder b;
  const int32_t x = b.add_activation("x", DType::kFloat32, {1, 4});
  const int32_t xq = b.add_activation("xq", DType::kInt8, {1, 4}, QuantSpec::per_tensor(0.1f, 0));
  const int32_t y = b.add_activation("y", DType::kFloat32, {1, 4});
  b.add_op(OpType::kQuantize, "q", {x}, xq);
  b.add_op(OpType::kDequantize, "dq", {xq}, y);
  b.set_inputs({x});
  b.set_outputs({y});
  auto mixed = testing::load_model(b.finish());
  ASSERT_NE(mixed, nullptr);
  std::vector<quantize::TensorRange> ranges(3, quantize::TensorRange{-1.0f, 1.0f});
  auto q = quantize::convert_to_int8(*mixed, ranges);
  ASSERT_FALSE(q.ok());
  EXPECT_NE(std::string(q.error().message()).find("already"), std::string::npos)
      << q.error().message();
}

}  // namespace
}  // namespace tlvlink
