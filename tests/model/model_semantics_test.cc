// Each crafted inconsistency is rejected with an error naming the tensor or operator at fault.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "model/tiny_models.h"
#include "support/test_models.h"

namespace tlvlink::testing {
namespace {

using quantize::ModelBuilder;
using quantize::QuantSpec;

void expect_rejected(const TinyInt8Model& m, ErrorCode code, const std::string& fragment) {
  const Error e = load_error(m.build());
  EXPECT_EQ(e.code(), code) << "message: " << e.message();
  EXPECT_NE(std::string(e.message()).find(fragment), std::string::npos)
      << "message '" << e.message() << "' should mention '" << fragment << "'";
}

TEST(ModelSemantics, TinyModelIsValid) {
  auto model = load_model(TinyInt8Model().build());
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->graph().operators.size(), 6u);
}

TEST(ModelSemantics, ScaleCountMustMatchChannels) {
  TinyInt8Model m;
  m.conv_weight_scales.pop_back();
  expect_rejected(m, ErrorCode::kModelInvalidTensor, "'conv.weight' has 3 scales for 4 channels");
}

TEST(ModelSemantics, DenormalZeroInfNanScalesRejected) {
  for (float bad : {1e-42f, 0.0f, -0.01f, std::numeric_limits<float>::infinity(),
                    std::numeric_limits<float>::quiet_NaN()}) {
    TinyInt8Model m;
    m.conv_weight_scales[2] = bad;
    SCOPED_TRACE(bad);
    expect_rejected(m, ErrorCode::kModelInvalidTensor, "'conv.weight' scale[2]");
  }
}

TEST(ModelSemantics, HugeAndTinyActivationScalesRejectedByRequantRange) {
  TinyInt8Model huge;
  huge.output_scale = 1e-30f;  // multiplier s_in*s_w/s_out >> 256
  expect_rejected(huge, ErrorCode::kModelInvalidOperator, "operator 1 Conv2D 'conv'");
  TinyInt8Model tiny;
  tiny.output_scale = 1e30f;  // multiplier < 2^-31: output would flush to zero
  expect_rejected(tiny, ErrorCode::kModelInvalidOperator, "requantization multiplier");
}

TEST(ModelSemantics, ZeroPointOutOfRange) {
  TinyInt8Model m;
  m.conv_zero_point = 200;
  expect_rejected(m, ErrorCode::kModelInvalidTensor, "'conv.out' zero_point[0] = 200");
}

TEST(ModelSemantics, WeightOfMinus128Rejected) {
  TinyInt8Model m;
  m.conv_weights[5] = -128;
  expect_rejected(m, ErrorCode::kModelInvalidOperator, "is -128");
}

TEST(ModelSemantics, PerChannelAxisMustBeOutputChannel) {
  TinyInt8Model m;
  m.conv_weight_scales = {0.01f, 0.01f, 0.01f};  // 3 entries along axis 3 (input channels)
  m.conv_weight_axis = 3;
  m.conv_has_bias = false;
  expect_rejected(m, ErrorCode::kModelInvalidOperator, "quantized along axis 3");
}

TEST(ModelSemantics, BiasScaleMustBeInputTimesWeightScale) {
  TinyInt8Model m;
  m.bias_scale_override = 0.5f;
  expect_rejected(m, ErrorCode::kModelInvalidOperator, "bias scale[0]");
}

TEST(ModelSemantics, AccumulatorBoundEnforced) {
  TinyInt8Model m;
  m.conv_bias[1] = 2147480000;  // |bias| + 255*sum|w| overflows int32
  expect_rejected(m, ErrorCode::kModelInvalidOperator, "worst-case accumulator");
}

TEST(ModelSemantics, ConvOutputShapeChecked) {
  TinyInt8Model m;
  m.conv_output_shape = {1, 7, 8, 4};
  expect_rejected(m, ErrorCode::kModelInvalidOperator, "expected [1,8,8,4]");
}

TEST(ModelSemantics, GroupsMustDivideChannels) {
  TinyInt8Model m;
  m.conv.groups = 2;  // 3 input channels
  expect_rejected(m, ErrorCode::kModelInvalidOperator, "groups 2 must divide");
}

TEST(ModelSemantics, ReadBeforeWriteRejected) {
  TinyInt8Model m;
  m.tweak = [](ModelBuilder& b) {
    const int32_t late = b.add_activation("late", DType::kFloat32, {1, 2});
    const int32_t out2 = b.add_activation("out2", DType::kFloat32, {1, 2});
    b.add_op(OpType::kClamp, "uses_late", {late}, out2, ClampParams{0, 1});
  };
  expect_rejected(m, ErrorCode::kModelInvalidOperator, "reads tensor 10 'late' before");
}

TEST(ModelSemantics, TwoProducersRejected) {
  TinyInt8Model m;
  m.tweak = [](ModelBuilder& b) {
    b.add_op(OpType::kClamp, "rewrites_output", {9}, 9, ClampParams{0, 1});
  };
  expect_rejected(m, ErrorCode::kModelInvalidOperator, "already written");
}

TEST(ModelSemantics, IndexOutOfRangeRejected) {
  TinyInt8Model m;
  m.tweak = [](ModelBuilder& b) {
    const int32_t o = b.add_activation("o", DType::kFloat32, {1, 2});
    b.add_op(OpType::kClamp, "bad_index", {4242}, o, ClampParams{0, 1});
  };
  expect_rejected(m, ErrorCode::kModelInvalidOperator, "refers to tensor 4242");
}

TEST(ModelSemantics, SigmoidInt8OutputQuantizationFixed) {
  TinyInt8Model m;
  m.tweak = [](ModelBuilder& b) {
    const int32_t s = b.add_activation("sig", DType::kInt8, {1, 2}, QuantSpec::per_tensor(0.1f, 0));
    b.add_op(OpType::kSigmoid, "sigmoid", {8}, s);
  };
  expect_rejected(m, ErrorCode::kModelInvalidOperator, "scale 1/256 and zero point -128");
}

// An int8 activation read by an operator through a per-channel QuantSpec (3 scales, axis 3).
std::vector<std::byte> per_channel_activation_model(OpType type) {
  ModelBuilder b;
  const int32_t x = b.add_activation("x_q", DType::kInt8, {1, 4, 4, 3},
                                     QuantSpec::per_channel({0.1f, 0.2f, 0.3f}, 3));
  if (type == OpType::kConv2D) {  // the reference read scale[0], XNNPACK refused at creation
    const std::vector<int8_t> w(2 * 3, 1);
    const int32_t wt = b.add_constant<int8_t>("conv.weight", {2, 1, 1, 3}, w,
                                              QuantSpec::per_channel({0.01f, 0.01f}, 0));
    const int32_t y =
        b.add_activation("y", DType::kInt8, {1, 4, 4, 2}, QuantSpec::per_tensor(0.1f, 0));
    b.add_op(OpType::kConv2D, "conv", {x, wt, kNoTensor}, y, Conv2DParams{});  // 1x1
    b.set_outputs({y});
  } else {
    const int32_t y = b.add_activation("y", DType::kInt8, {1, 4, 4, 3},
                                       QuantSpec::per_channel({0.1f, 0.2f, 0.3f}, 3));
    b.add_op(type, "pool", {x}, y, Pool2DParams{});  // 1x1, a pass-through
    b.set_outputs({y});
  }
  b.set_inputs({x});
  return b.finish();
}

TEST(ModelSemantics, PerChannelActivationRejectedForEveryOperator) {
  for (OpType type : {OpType::kConv2D, OpType::kMaxPool2D}) {
    SCOPED_TRACE(op_type_name(type));
    const Error e = load_error(per_channel_activation_model(type));
    EXPECT_EQ(e.code(), ErrorCode::kModelInvalidOperator) << e.message();
    const std::string fragments[] = {
        std::string("operator 0 ") + op_type_name(type),
        "input tensor 0 'x_q' is quantized per-channel (3 scales along axis 3)"};
    for (const std::string& fragment : fragments) {
      EXPECT_NE(std::string(e.message()).find(fragment), std::string::npos)
          << "message '" << e.message() << "' should mention '" << fragment << "'";
    }
  }
}

TEST(ModelSemantics, PerChannelUnusedGraphInputRejected) {
  TinyInt8Model m;
  m.tweak = [](ModelBuilder& b) {
    const int32_t side =
        b.add_activation("side_q", DType::kInt8, {1, 2}, QuantSpec::per_channel({0.1f, 0.2f}, 1));
    b.set_inputs({0, side});
  };
  expect_rejected(m, ErrorCode::kModelInvalidTensor,
                  "graph input tensor 10 'side_q' is quantized per-channel");
}

// Fuzzer regression: XNNPACK asserted creating a runtime for an unread ResizeBilinear result.
TEST(ModelSemantics, DeadOperatorRejected) {
  TinyInt8Model m;
  m.tweak = [](ModelBuilder& b) {
    const int32_t r = b.add_activation("resize.out", DType::kInt8, {1, 4, 4, 4},
                                       QuantSpec::per_tensor(0.05f, -10));
    b.add_op(OpType::kResizeBilinear, "resize", {4}, r, ResizeBilinearParams{});
  };
  expect_rejected(m, ErrorCode::kModelInvalidOperator,
                  "operator 6 ResizeBilinear 'resize' writes tensor 10 'resize.out', which no "
                  "operator reads");
}

TEST(ModelSemantics, NonFiniteFloatWeightsNamed) {
  ModelBuilder b;
  std::vector<float> w(2 * 3, 0.5f);
  w[4] = std::numeric_limits<float>::quiet_NaN();
  const int32_t x = b.add_activation("x", DType::kFloat32, {1, 3});
  const int32_t wt = b.add_constant<float>("head.weight", {2, 3}, w);
  const int32_t y = b.add_activation("y", DType::kFloat32, {1, 2});
  b.add_op(OpType::kFullyConnected, "head", {x, wt, kNoTensor}, y);
  b.set_inputs({x});
  b.set_outputs({y});
  const Error e = load_error(b.finish());
  EXPECT_EQ(e.code(), ErrorCode::kModelInvalidTensor);
  EXPECT_NE(std::string(e.message()).find("'head.weight' element 4 is nan"), std::string::npos)
      << e.message();
}

TEST(ModelSemantics, WrongOptionsTypeRejected) {
  TinyInt8Model m;
  m.tweak = [](ModelBuilder& b) {
    const int32_t o = b.add_activation("o", DType::kFloat32, {1, 2});
    b.add_op(OpType::kClamp, "clamp_without_range", {9}, o, BinaryParams{});
  };
  expect_rejected(m, ErrorCode::kModelInvalidOperator, "has options of type BinaryOptions");
}

TEST(ModelSemantics, ReshapeElementCountChecked) {
  TinyInt8Model m;
  m.tweak = [](ModelBuilder& b) {
    const int32_t o = b.add_activation("o", DType::kFloat32, {1, 3});
    b.add_op(OpType::kReshape, "bad_reshape", {9}, o);
  };
  expect_rejected(m, ErrorCode::kModelInvalidOperator, "cannot reshape");
}

TEST(ModelSemantics, LinearHeadSizeChecked) {
  TinyInt8Model m;
  m.tweak = [](ModelBuilder& b) {
    b.metadata().linear_heads.push_back({"material", {"wood", "metal"}, {1, 2, 3}, {0, 0}});
  };
  expect_rejected(m, ErrorCode::kModelInvalidMetadata, "linear head 'material'");
}

TEST(ModelSemantics, GoldenPairSizeChecked) {
  TinyInt8Model m;
  m.tweak = [](ModelBuilder& b) {
    b.metadata().golden.push_back({std::vector<std::byte>(4), std::vector<std::byte>(8)});
  };
  expect_rejected(m, ErrorCode::kModelInvalidMetadata, "golden pair 0");
}

TEST(ModelSemantics, InputSpecMustMatchGraphInput) {
  TinyInt8Model m;
  m.tweak = [](ModelBuilder& b) {
    auto& in = b.metadata().input;
    in.height = 16;
    in.width = 16;
    in.channels = 3;
    in.mean = {0.5f, 0.5f, 0.5f};
    in.std = {0.25f, 0.25f, 0.25f};
  };
  expect_rejected(m, ErrorCode::kModelInvalidMetadata, "does not match graph input 0");
}

}  // namespace
}  // namespace tlvlink::testing
