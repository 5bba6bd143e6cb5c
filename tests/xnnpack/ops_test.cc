// Per-operator agreement of the XNNPACK executor with the reference executor, fp32 and int8
// (see harness.h for the tolerances and how they are derived).
#include <gtest/gtest.h>

#include "xnnpack/graphs.h"
#include "xnnpack/harness.h"

namespace tlvlink::testing {
namespace {

class XnnpackOpTest : public ::testing::Test {
 protected:
  void check(const TGraph& g, float in_range = 1.0f) {
    SCOPED_SEED_TRACE(seed_);
    check_graph(g, rng_, agg_, in_range);
  }
  void TearDown() override {
    std::printf("[ agreement ] %s\n", agg_.summary().c_str());
    EXPECT_GT(agg_.int8_elements, 0u);
    EXPECT_GT(agg_.float_elements, 0u);
  }
  uint64_t seed_ = test_seed();
  Rng rng_{seed_};
  Agreement agg_;
};

TEST_F(XnnpackOpTest, Conv2DDense) {
  ConvCase c;
  check(conv_graph(c, rng_));
  c.activation = Activation::kRelu6;
  c.stride_h = c.stride_w = 2;
  check(conv_graph(c, rng_));
  ConvCase pointwise;
  pointwise.kh = pointwise.kw = 1;
  pointwise.pad_top = pointwise.pad_bottom = pointwise.pad_left = pointwise.pad_right = 0;
  pointwise.cin = 24, pointwise.cout = 16, pointwise.activation = Activation::kRelu;
  check(conv_graph(pointwise, rng_));
}

TEST_F(XnnpackOpTest, Conv2DStemThreeChannelsNoBias) {
  ConvCase c;
  c.h = c.w = 16, c.cin = 3, c.cout = 16, c.stride_h = c.stride_w = 2, c.bias = false;
  c.pad_top = c.pad_left = 0;  // asymmetric "same" padding as TF exports it
  check(conv_graph(c, rng_));
}

TEST_F(XnnpackOpTest, Conv2DDilated) {
  ConvCase c;
  c.dilation_h = c.dilation_w = 2;
  c.pad_top = c.pad_bottom = c.pad_left = c.pad_right = 2;
  check(conv_graph(c, rng_));
}

TEST_F(XnnpackOpTest, Conv2DGrouped) {
  ConvCase c;
  c.cin = 8, c.cout = 12, c.groups = 4;
  check(conv_graph(c, rng_));
}

TEST_F(XnnpackOpTest, DepthwiseConv) {
  ConvCase c;
  c.cin = c.cout = c.groups = 16;
  c.activation = Activation::kRelu6;
  check(conv_graph(c, rng_));
  c.stride_h = c.stride_w = 2;
  c.cout = 32;  // depth multiplier 2
  check(conv_graph(c, rng_));
}

TEST_F(XnnpackOpTest, FullyConnected) {
  check(fc_graph(1, 64, 10, true, Activation::kNone, rng_));
  check(fc_graph(3, 17, 5, false, Activation::kRelu, rng_));
}

TEST_F(XnnpackOpTest, AddSameShapeAndBroadcast) {
  check(binary_graph(OpType::kAdd, {1, 4, 5, 8}, {1, 4, 5, 8}, false, Activation::kNone, rng_));
  check(binary_graph(OpType::kAdd, {2, 4, 5, 8}, {8}, true, Activation::kRelu, rng_));
  check(binary_graph(OpType::kAdd, {1, 4, 1, 8}, {1, 1, 5, 1}, false, Activation::kRelu6, rng_));
}

TEST_F(XnnpackOpTest, MulSameShapeAndBroadcast) {
  check(binary_graph(OpType::kMul, {1, 4, 5, 8}, {1, 4, 5, 8}, false, Activation::kNone, rng_));
  check(binary_graph(OpType::kMul, {1, 4, 5, 8}, {1, 1, 1, 8}, true, Activation::kNone, rng_));
  check(binary_graph(OpType::kMul, {3, 1, 6}, {1, 7, 1}, false, Activation::kRelu, rng_));
}

TEST_F(XnnpackOpTest, Clamp) {
  check(unary_graph(OpType::kClamp, {1, 6, 6, 4}, {1, 6, 6, 4}, ClampParams{-0.25f, 0.5f}));
}

TEST_F(XnnpackOpTest, Sigmoid) {
  check(unary_graph(OpType::kSigmoid, {1, 6, 6, 4}, {1, 6, 6, 4}), 6.0f);
}

TEST_F(XnnpackOpTest, GlobalAveragePool) {
  check(unary_graph(OpType::kGlobalAveragePool, {2, 7, 5, 12}, {2, 1, 1, 12}));
}

TEST_F(XnnpackOpTest, MaxPool) {
  Pool2DParams p;
  p.pool_h = p.pool_w = 3;
  p.stride_h = p.stride_w = 2;
  p.pad_top = p.pad_left = p.pad_bottom = p.pad_right = 1;
  check(unary_graph(OpType::kMaxPool2D, {1, 9, 9, 5}, {1, 5, 5, 5}, p));
  Pool2DParams q;
  q.pool_h = q.pool_w = 2;
  q.stride_h = q.stride_w = 2;
  check(unary_graph(OpType::kMaxPool2D, {1, 8, 6, 3}, {1, 4, 3, 3}, q));
}

TEST_F(XnnpackOpTest, Pad) {
  PadParams p;
  p.before = {0, 1, 2, 0};
  p.after = {0, 2, 1, 1};
  p.value = 0.0f;
  check(unary_graph(OpType::kPad, {1, 4, 4, 3}, {1, 7, 7, 4}, p));
  p.value = 0.5f;  // a real value, quantized on the output grid for int8
  check(unary_graph(OpType::kPad, {1, 4, 4, 3}, {1, 7, 7, 4}, p));
}

TEST_F(XnnpackOpTest, Reshape) { check(unary_graph(OpType::kReshape, {1, 2, 3, 4}, {6, 4})); }

TEST_F(XnnpackOpTest, ResizeBilinear) {
  check(unary_graph(OpType::kResizeBilinear, {1, 5, 7, 3}, {1, 10, 13, 3},
                    ResizeBilinearParams{false}));
  check(
      unary_graph(OpType::kResizeBilinear, {1, 5, 7, 3}, {1, 9, 4, 3}, ResizeBilinearParams{true}));
  check(unary_graph(OpType::kResizeBilinear, {1, 8, 8, 2}, {1, 3, 5, 2},
                    ResizeBilinearParams{false}));
}

}  // namespace
}  // namespace tlvlink::testing
