#include "reference/all_ops_models.h"

#include <cmath>
#include <string>
#include <utility>

#include "reference/ref_util.h"

namespace tlvlink::reference_test {
namespace {

// Deterministic weights in [-0.3, 0.3] (the graph's values do not matter, only its coverage).
std::vector<float> weights(size_t n, float phase) {
  std::vector<float> w(n);
  for (size_t i = 0; i < n; ++i) w[i] = 0.3f * std::sin(phase + 0.7f * static_cast<float>(i));
  return w;
}

class ChainBuilder {
 public:
  explicit ChainBuilder(bool int8) : int8_(int8) {}

  int32_t activation(const std::string& name, std::vector<int32_t> shape, QParams q = kAct) {
    return int8_ ? b.add_activation(name, DType::kInt8, std::move(shape), q.spec())
                 : b.add_activation(name, DType::kFloat32, std::move(shape));
  }
  // Conv / FC weights (per-channel int8) and bias for an input with scale in_scale.
  std::pair<int32_t, int32_t> weights_and_bias(const std::string& name, std::vector<int32_t> shape,
                                               float phase) {
    size_t n = 1;
    for (int32_t d : shape) n *= static_cast<size_t>(d);
    const std::vector<float> w = weights(n, phase);
    const std::vector<float> bias = weights(static_cast<size_t>(shape[0]), phase + 1);
    if (!int8_) {
      return {b.add_constant<float>(name + ".w", shape, std::span<const float>(w)),
              b.add_constant<float>(name + ".b", {shape[0]}, std::span<const float>(bias))};
    }
    const auto q = testing::quantize_weights_per_channel(w, shape[0]);
    const auto qb = testing::quantize_bias(bias, kAct.scale, q.scales);
    std::vector<float> bias_scales;
    for (float s : q.scales) bias_scales.push_back(kAct.scale * s);
    return {b.add_constant<int8_t>(name + ".w", shape, std::span<const int8_t>(q.values),
                                   QuantSpec::per_channel(q.scales, 0)),
            b.add_constant<int32_t>(name + ".b", {shape[0]}, std::span<const int32_t>(qb),
                                    QuantSpec::per_channel(bias_scales, 0))};
  }

  static constexpr QParams kAct{0.05f, 0};
  ModelBuilder b;

 private:
  bool int8_;
};

}  // namespace

std::vector<std::byte> all_ops_model(bool int8) {
  ChainBuilder c(int8);
  ModelBuilder& b = c.b;
  const int32_t x = b.add_activation("frame", DType::kFloat32, {1, 8, 8, 4});
  int32_t t = x;
  if (int8) {
    t = c.activation("quantized", {1, 8, 8, 4});
    b.add_op(OpType::kQuantize, "quantize", {x}, t);
  }
  auto [w1, b1] = c.weights_and_bias("conv", {6, 3, 3, 4}, 0.1f);
  const int32_t conv = c.activation("conv.out", {1, 8, 8, 6});
  b.add_op(OpType::kConv2D, "conv", {t, w1, b1}, conv,
           Conv2DParams{3, 3, 1, 1, 1, 1, 1, 1, 1, 1, 1, Activation::kRelu});
  auto [w2, b2] = c.weights_and_bias("dw", {6, 3, 3, 1}, 0.2f);
  const int32_t dw = c.activation("dw.out", {1, 4, 4, 6});
  b.add_op(OpType::kConv2D, "dw", {conv, w2, b2}, dw,
           Conv2DParams{3, 3, 2, 2, 1, 1, 0, 1, 0, 1, 6, Activation::kNone});
  const int32_t pool = c.activation("pool.out", {1, 4, 4, 6});
  b.add_op(OpType::kMaxPool2D, "pool", {dw}, pool, Pool2DParams{2, 2, 1, 1, 0, 1, 0, 1});
  const int32_t add = c.activation("add.out", {1, 4, 4, 6});
  b.add_op(OpType::kAdd, "add", {dw, pool}, add, BinaryParams{Activation::kRelu6});
  const std::vector<float> gain{0.5f, -1, 2, 1, -0.25f, 1.5f};
  const std::vector<int8_t> gain_q{50, -100, 127, 100, -25, 127};  // scale 0.01 (2 saturates)
  const int32_t g = int8 ? b.add_constant<int8_t>("gain", {6}, std::span<const int8_t>(gain_q),
                                                  QuantSpec::per_tensor(0.01f, 0))
                         : b.add_constant<float>("gain", {6}, std::span<const float>(gain));
  const int32_t mul = c.activation("mul.out", {1, 4, 4, 6});
  b.add_op(OpType::kMul, "mul", {add, g}, mul, BinaryParams{});
  const int32_t clamp = c.activation("clamp.out", {1, 4, 4, 6});
  b.add_op(OpType::kClamp, "clamp", {mul}, clamp, ClampParams{-1, 1});
  PadParams pp;
  pp.before = {0, 1, 1, 0};
  pp.after = {0, 1, 1, 0};
  const int32_t pad = c.activation("pad.out", {1, 6, 6, 6});
  b.add_op(OpType::kPad, "pad", {clamp}, pad, pp);
  const int32_t resize = c.activation("resize.out", {1, 3, 3, 6});
  b.add_op(OpType::kResizeBilinear, "resize", {pad}, resize, ResizeBilinearParams{});
  const int32_t gap = c.activation("gap.out", {1, 1, 1, 6});
  b.add_op(OpType::kGlobalAveragePool, "gap", {resize}, gap);
  const int32_t flat = c.activation("flat", {1, 6});
  b.add_op(OpType::kReshape, "flatten", {gap}, flat);
  auto [w3, b3] = c.weights_and_bias("fc", {3, 6}, 0.3f);
  const int32_t fc = c.activation("fc.out", {1, 3});
  b.add_op(OpType::kFullyConnected, "fc", {flat, w3, b3}, fc, FullyConnectedParams{});
  const int32_t sig = c.activation("sigmoid.out", {1, 3}, QParams{1.0f / 256, -128});
  b.add_op(OpType::kSigmoid, "sigmoid", {fc}, sig);
  int32_t y = sig;
  if (int8) {
    y = b.add_activation("embedding", DType::kFloat32, {1, 3});
    b.add_op(OpType::kDequantize, "dequantize", {sig}, y);
  }
  b.set_inputs({x});
  b.set_outputs({y});
  return b.finish();
}

}  // namespace tlvlink::reference_test
