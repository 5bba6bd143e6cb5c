// The numerical edge cases of the int8 scheme (calibrate.h), one test each: zero-range tensors,
// denormal / huge scales, weights that would round to -128, bias overflow after BatchNorm
// folding, accumulator bounds, requantization multipliers out of range (conv, Add, GAP), pad
// values outside the int8 range, NaN/Inf weights and activations. Each one either meets the int8
// constraints with a stated adjustment or leaves that one layer in fp32 with its reason.

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "quantizer/quantizer_graphs.h"
#include "quantizer/quantizer_internal.h"
#include "support/test_models.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::quantizer_test {
namespace {

using quantize::LayerPrecision;
using quantize::ModelBuilder;
using quantize::TensorRange;
using namespace quantize::quantizer_internal;

TEST(EdgeCases, ZeroRangeTensorGetsAFlooredNormalScaleAndExactZeros) {
  // A dead conv: zero weights and bias, so its output is constant 0 on every frame.
  auto fp32 = testing::load_model(conv_model(4, 4, 2, 3, 1, std::vector<float>(6, 0.0f),
                                             std::vector<float>(3, 0.0f), Activation::kRelu));
  ASSERT_NE(fp32, nullptr);
  auto q = quantize_for_test(*fp32, random_frames(4, 32, -1.0f, 1.0f, 1));
  ASSERT_NE(q, nullptr);
  EXPECT_EQ(decision(q->q, "conv")->precision, LayerPrecision::kInt8);
  const Tensor& out = q->model->graph().tensor(producer_of(*q->model, "conv.q")->output);
  EXPECT_TRUE(std::isnormal(out.quant.scale[0]));
  EXPECT_FLOAT_EQ(out.quant.scale[0], quantize::kMinActivationRange / 255.0f);
  for (float v : run(*q->model, random_frames(1, 32, -1.0f, 1.0f, 2)[0])) EXPECT_EQ(v, 0.0f);
}

TEST(EdgeCases, ActivationScalesAreNeverDenormalOrInfinite) {
  TensorRange tiny{0.0f, 1e-42f};  // a denormal range
  ActivationParams p = activation_params(tiny, quantize::kMinActivationRange);
  ASSERT_TRUE(p.failure.empty());
  EXPECT_TRUE(std::isnormal(p.spec.scale[0]));
  // hi - lo overflows float; computed in double it is a finite normal scale.
  p = activation_params(TensorRange{-3e38f, 3e38f}, quantize::kMinActivationRange);
  ASSERT_TRUE(p.failure.empty()) << p.failure;
  EXPECT_TRUE(std::isfinite(p.spec.scale[0]) && std::isnormal(p.spec.scale[0]));
  // No range at all (never observed) or a non-finite one: a reason, not a scale.
  EXPECT_FALSE(activation_params(TensorRange{}, quantize::kMinActivationRange).failure.empty());
  EXPECT_FALSE(activation_params(TensorRange{0.0f, std::numeric_limits<float>::infinity()},
                                 quantize::kMinActivationRange)
                   .failure.empty());
}

TEST(EdgeCases, DenormalWeightsGetANormalScaleAndQuantizeToZero) {
  LinearRequest r;
  const std::vector<float> w(8, 1e-40f);
  r.weights = w;
  r.cout = 2;
  r.input_scale = 1.0f / 255.0f;
  r.output_scale = 1.0f / 255.0f;
  const LinearWeights lw = quantize_linear(r);
  ASSERT_TRUE(lw.failure.empty()) << lw.failure;
  for (float s : lw.scales) EXPECT_TRUE(std::isnormal(s));
  for (int8_t v : lw.values) EXPECT_EQ(v, 0);
}

TEST(EdgeCases, WeightsNeverRoundToMinus128) {
  // A scale a hair too small for the most negative weight would give -128; it is clamped.
  const std::vector<float> w = {-1.0f, 0.5f, 1.0f};
  std::vector<int8_t> q(3);
  quantize_symmetric(w, 1.0f / 127.6f, q);
  EXPECT_EQ(q[0], -127);
  EXPECT_EQ(q[2], 127);
  // Through quantize_linear, an asymmetric channel's extreme is exactly -127.
  LinearRequest r;
  const std::vector<float> channel = {-2.0f, 0.3f, 1.1f, -0.7f};
  r.weights = channel;
  r.cout = 1;
  r.input_scale = r.output_scale = 0.01f;
  const LinearWeights lw = quantize_linear(r);
  EXPECT_EQ(*std::min_element(lw.values.begin(), lw.values.end()), -127);
}

// A conv whose BatchNorm folded into tiny weights (gamma ~ 1e-7) and a large bias.
std::vector<std::byte> bn_folded_conv(float weight, float bias) {
  return conv_model(4, 4, 2, 2, 1, std::vector<float>(4, weight), std::vector<float>(2, bias));
}

TEST(EdgeCases, BiasOverflowAfterBnFoldingRaisesTheWeightScaleWhenCheap) {
  // s_in ~ 2/255, s_w = 2^-20 (the floor; 2e-7/127 is below it): bias 30 / (s_in s_w) = 4e9 >
  // 2^30 -> weight scale raised x3.7 (<= 16).
  auto fp32 = testing::load_model(bn_folded_conv(2e-7f, 30.0f));
  ASSERT_NE(fp32, nullptr);
  auto q = quantize_for_test(*fp32, random_frames(8, 32, -1.0f, 1.0f, 3));
  ASSERT_NE(q, nullptr);
  const quantize::LayerDecision* d = decision(q->q, "conv");
  EXPECT_EQ(d->precision, LayerPrecision::kInt8);
  ASSERT_FALSE(d->adjustments.empty());
  EXPECT_NE(d->adjustments[0].find("bias"), std::string::npos) << d->adjustments[0];
  // The output is the bias: still right to within an output step.
  const float s_out =
      q->model->graph().tensor(producer_of(*q->model, "conv.q")->output).quant.scale[0];
  for (float v : run(*q->model, random_frames(1, 32, -1.0f, 1.0f, 4)[0]))
    EXPECT_NEAR(v, 30.0f, s_out);
}

TEST(EdgeCases, BiasOverflowBeyondTheAllowedRaiseKeepsTheLayerFp32) {
  // bias 1000 needs the scale raised ~125x: more than max_bias_scale_raise (16).
  auto fp32 = testing::load_model(bn_folded_conv(2e-7f, 1000.0f));
  ASSERT_NE(fp32, nullptr);
  auto q = quantize_for_test(*fp32, random_frames(8, 32, -1.0f, 1.0f, 3));
  ASSERT_NE(q, nullptr);
  const quantize::LayerDecision* d = decision(q->q, "conv");
  EXPECT_EQ(d->precision, LayerPrecision::kFloat);
  EXPECT_NE(d->reason.find("bias"), std::string::npos) << d->reason;
  // Allowing a larger raise keeps it int8, stated.
  quantize::QuantizerOptions o;
  o.max_bias_scale_raise = 1000;
  auto q2 = quantize_for_test(*fp32, random_frames(8, 32, -1.0f, 1.0f, 3), o);
  ASSERT_NE(q2, nullptr);
  EXPECT_EQ(decision(q2->q, "conv")->precision, LayerPrecision::kInt8);
  EXPECT_FALSE(decision(q2->q, "conv")->adjustments.empty());
}

TEST(EdgeCases, AccumulatorBoundKeepsAHugeFullyConnectedFp32) {
  // K = 70000: 255 * 127 * K = 2.27e9 >= 2^31 for a channel of equal-magnitude weights.
  constexpr int32_t kK = 70000;
  ModelBuilder b;
  const int32_t x = b.add_activation("x", DType::kFloat32, {1, kK});
  const std::vector<float> w(kK, 0.01f);
  const int32_t wt = b.add_constant<float>("fc.w", {1, kK}, w);
  const int32_t y = b.add_activation("y", DType::kFloat32, {1, 1});
  b.add_op(OpType::kFullyConnected, "fc", {x, wt, kNoTensor}, y, FullyConnectedParams{});
  b.set_inputs({x});
  b.set_outputs({y});
  auto fp32 = testing::load_model(b.finish());
  ASSERT_NE(fp32, nullptr);
  auto q = quantize_for_test(*fp32, random_frames(2, kK, -1.0f, 1.0f, 5));
  ASSERT_NE(q, nullptr);
  const quantize::LayerDecision* d = decision(q->q, "fc");
  EXPECT_EQ(d->precision, LayerPrecision::kFloat);
  EXPECT_NE(d->reason.find("accumulator"), std::string::npos) << d->reason;
}

TEST(EdgeCases, NegligibleChannelMultiplierBelow2PowMinus31IsRaisedAndStated) {
  // Channel 0 drives the output range to [0, 2000]; channel 1 is dead (zero weights): its weight
  // scale floor (2^-20) with a 0.01-wide input would give a multiplier ~5e-12.
  const std::vector<float> w = {1e5f, 1e5f, 0.0f, 0.0f};
  auto fp32 = testing::load_model(conv_model(4, 4, 2, 2, 1, w, {}));
  ASSERT_NE(fp32, nullptr);
  auto q = quantize_for_test(*fp32, random_frames(8, 32, 0.0f, 0.01f, 6));
  ASSERT_NE(q, nullptr);
  const quantize::LayerDecision* d = decision(q->q, "conv");
  EXPECT_EQ(d->precision, LayerPrecision::kInt8);
  ASSERT_EQ(d->adjustments.size(), 1u);
  EXPECT_NE(d->adjustments[0].find("channel 1"), std::string::npos) << d->adjustments[0];
  EXPECT_NE(d->adjustments[0].find("2^-31"), std::string::npos) << d->adjustments[0];
}

TEST(EdgeCases, ConvMultiplierAbove256KeepsTheLayerFp32) {
  // Two identical input channels and weights (1, -1): the output is always exactly 0, so its
  // range is floored to 2^-12 while s_in * s_w is ~3e-3: multiplier ~3000.
  auto fp32 = testing::load_model(conv_model(4, 4, 2, 1, 1, {1.0f, -1.0f}, {}));
  ASSERT_NE(fp32, nullptr);
  auto frames = random_frames(4, 32, 0.0f, 100.0f, 7);
  for (auto& f : frames)
    for (size_t i = 0; i < f.size(); i += 2) f[i + 1] = f[i];
  auto q = quantize_for_test(*fp32, frames);
  ASSERT_NE(q, nullptr);
  const quantize::LayerDecision* d = decision(q->q, "conv");
  EXPECT_EQ(d->precision, LayerPrecision::kFloat);
  EXPECT_NE(d->reason.find(">= 256"), std::string::npos) << d->reason;
}

TEST(EdgeCases, AddWithANegligibleOperandOutsideXnnpackRatioStaysFp32) {
  ModelBuilder b;
  const int32_t x = b.add_activation("x", DType::kFloat32, {1, 2, 2, 1});
  const int32_t wa = b.add_constant<float>("a.w", {1, 1, 1, 1}, std::vector<float>{1000.0f});
  const int32_t wb = b.add_constant<float>("b.w", {1, 1, 1, 1}, std::vector<float>{1e-5f});
  const int32_t a = b.add_activation("a", DType::kFloat32, {1, 2, 2, 1});
  const int32_t c = b.add_activation("b", DType::kFloat32, {1, 2, 2, 1});
  b.add_op(OpType::kConv2D, "a", {x, wa, kNoTensor}, a, Conv2DParams{});
  b.add_op(OpType::kConv2D, "b", {x, wb, kNoTensor}, c, Conv2DParams{});
  const int32_t y = b.add_activation("sum", DType::kFloat32, {1, 2, 2, 1});
  b.add_op(OpType::kAdd, "sum", {a, c}, y, BinaryParams{});
  b.set_inputs({x});
  b.set_outputs({y});
  auto fp32 = testing::load_model(b.finish());
  ASSERT_NE(fp32, nullptr);
  auto q = quantize_for_test(*fp32, random_frames(4, 4, -1.0f, 1.0f, 8));
  ASSERT_NE(q, nullptr);
  const quantize::LayerDecision* d = decision(q->q, "sum");
  EXPECT_EQ(d->precision, LayerPrecision::kFloat);
  EXPECT_NE(d->reason.find("Add"), std::string::npos) << d->reason;
  EXPECT_EQ(decision(q->q, "a")->precision, LayerPrecision::kInt8);
}

TEST(EdgeCases, GlobalAveragePoolOfACancellingPatternStaysFp32) {
  // A +-100 checkerboard averages to exactly 0: the output range is floored, s_in/s_out ~ 2e5.
  ModelBuilder b;
  const int32_t x = b.add_activation("x", DType::kFloat32, {1, 2, 2, 1});
  const int32_t g = b.add_activation("gap", DType::kFloat32, {1, 1, 1, 1});
  b.add_op(OpType::kGlobalAveragePool, "gap", {x}, g);
  b.set_inputs({x});
  b.set_outputs({g});
  auto fp32 = testing::load_model(b.finish());
  ASSERT_NE(fp32, nullptr);
  const std::vector<std::vector<float>> frames = {{100.0f, -100.0f, -100.0f, 100.0f}};
  auto q = quantize_for_test(*fp32, frames);
  ASSERT_NE(q, nullptr);
  const quantize::LayerDecision* d = decision(q->q, "gap");
  EXPECT_EQ(d->precision, LayerPrecision::kFloat);
  EXPECT_NE(d->reason.find("GlobalAveragePool"), std::string::npos) << d->reason;
}

TEST(EdgeCases, PadValueOutsideTheInputInt8RangeStaysFp32) {
  ModelBuilder b;
  const int32_t x = b.add_activation("x", DType::kFloat32, {1, 2, 2, 1});
  const int32_t w = b.add_constant<float>("c.w", {1, 1, 1, 1}, std::vector<float>{1.0f});
  const int32_t c = b.add_activation("c", DType::kFloat32, {1, 2, 2, 1});
  Conv2DParams cp;
  cp.activation = Activation::kRelu6;
  b.add_op(OpType::kConv2D, "c", {x, w, kNoTensor}, c, cp);
  const int32_t p = b.add_activation("pad", DType::kFloat32, {1, 4, 4, 1});
  PadParams pp;
  pp.before = {0, 1, 1, 0};
  pp.after = {0, 1, 1, 0};
  pp.value = -5.0f;  // the ReLU6 output's int8 range is [0, 6]
  b.add_op(OpType::kPad, "pad", {c}, p, pp);
  b.set_inputs({x});
  b.set_outputs({p});
  auto fp32 = testing::load_model(b.finish());
  ASSERT_NE(fp32, nullptr);
  auto q = quantize_for_test(*fp32, random_frames(4, 4, 0.0f, 6.0f, 9));
  ASSERT_NE(q, nullptr);
  EXPECT_EQ(decision(q->q, "pad")->precision, LayerPrecision::kFloat);
  const std::vector<float> y = run(*q->model, {1.0f, 2.0f, 3.0f, 4.0f});
  EXPECT_EQ(y[0], -5.0f);  // the padding is exact
}

TEST(EdgeCases, NanOrInfWeightsAreRejectedNamingTheTensor) {
  for (float bad : {std::nanf(""), std::numeric_limits<float>::infinity()}) {
    const Error e = testing::load_error(conv_model(2, 2, 1, 1, 1, {bad}, {}));
    EXPECT_EQ(e.code(), ErrorCode::kModelInvalidTensor);
    EXPECT_NE(std::string(e.message()).find("conv.w"), std::string::npos) << e.message();
  }
}

TEST(EdgeCases, CalibrationOverflowToInfNamesTheTensor) {
  // Finite weights whose products overflow float: the activation becomes Inf at "conv".
  auto fp32 = testing::load_model(conv_model(2, 2, 1, 1, 1, {3e38f}, {}));
  ASSERT_NE(fp32, nullptr);
  auto stats = quantize::calibrate(*fp32, random_frames(1, 4, 10.0f, 20.0f, 1));
  ASSERT_FALSE(stats.ok());
  EXPECT_EQ(stats.error().code(), ErrorCode::kNonFiniteValue);
  EXPECT_NE(std::string(stats.error().message()).find("'conv'"), std::string::npos)
      << stats.error().message();
}

}  // namespace
}  // namespace tlvlink::quantizer_test
