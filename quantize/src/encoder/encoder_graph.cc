// The reference encoder's float graph: MobileNetV2-like, seeded He-style weights.

#include <cmath>
#include <string>

#include "encoder/encoder_internal.h"

namespace tlvlink::quantize::encoder_internal {
namespace {

struct Block {
  int32_t expansion, channels, stride;
};
constexpr int32_t kStemChannels = 16;
constexpr int32_t kHeadChannels = 256;
constexpr Block kBlocks[] = {{1, 16, 1}, {6, 24, 2}, {6, 24, 1}, {6, 32, 2},
                             {6, 32, 1}, {6, 48, 2}, {6, 48, 1}, {6, 64, 1}};
// Variance gains: 2 keeps ReLU-family activations at a steady scale (He); a linear projection
// gets 1 (LeCun), halved where a residual Add follows so the sum does not grow block by block.
constexpr float kReluGain = 2.0f;
constexpr float kLinearGain = 1.0f;
constexpr float kResidualGain = 0.5f;
constexpr float kBiasRange = 0.05f;

struct Value {
  int32_t tensor;
  int32_t h, w, c;
};

class NetBuilder {
 public:
  NetBuilder(EncoderGraph& g, uint64_t seed) : g_(g), rng_(seed) {}

  Value input(int32_t r) {
    const int32_t t = g_.builder.add_activation("input", DType::kFloat32, {1, r, r, 3});
    return {t, r, r, 3};
  }

  Value conv(const std::string& name, Value in, int32_t cout, int32_t k, int32_t stride,
             bool depthwise, Activation act, float gain) {
    const int32_t groups = depthwise ? in.c : 1;
    const int32_t cin_per_group = in.c / groups;
    const int32_t pad = k / 2;
    const int32_t oh = (in.h + 2 * pad - k) / stride + 1, ow = (in.w + 2 * pad - k) / stride + 1;
    const float std = std::sqrt(gain / static_cast<float>(k * k * cin_per_group));
    std::vector<float> w(static_cast<size_t>(cout) * k * k * cin_per_group),
        b(static_cast<size_t>(cout));
    for (float& v : w) v = std * rng_.normal();
    for (float& v : b) v = rng_.uniform(-kBiasRange, kBiasRange);
    const int32_t wt =
        g_.builder.add_constant<float>(name + ".weight", {cout, k, k, cin_per_group}, w);
    const int32_t bt = g_.builder.add_constant<float>(name + ".bias", {cout}, b);
    const int32_t out =
        g_.builder.add_activation(name + ".out", DType::kFloat32, {1, oh, ow, cout});
    Conv2DParams p;
    p.kernel_h = p.kernel_w = k;
    p.stride_h = p.stride_w = stride;
    p.pad_top = p.pad_bottom = p.pad_left = p.pad_right = pad;
    p.groups = groups;
    p.activation = act;
    g_.builder.add_op(OpType::kConv2D, name, {in.tensor, wt, bt}, out, p);
    count(name, static_cast<uint64_t>(oh) * ow * cout * k * k * cin_per_group);
    return {out, oh, ow, cout};
  }

  Value add(const std::string& name, Value a, Value b) {
    const int32_t out =
        g_.builder.add_activation(name + ".out", DType::kFloat32, {1, a.h, a.w, a.c});
    g_.builder.add_op(OpType::kAdd, name, {a.tensor, b.tensor}, out, BinaryParams{});
    return {out, a.h, a.w, a.c};
  }

  Value pool_and_flatten(Value in) {
    const int32_t pooled = g_.builder.add_activation("pool.out", DType::kFloat32, {1, 1, 1, in.c});
    g_.builder.add_op(OpType::kGlobalAveragePool, "pool", {in.tensor}, pooled);
    const int32_t flat = g_.builder.add_activation("flatten.out", DType::kFloat32, {1, in.c});
    g_.builder.add_op(OpType::kReshape, "flatten", {pooled}, flat);
    return {flat, 1, 1, in.c};
  }

  Value fully_connected(const std::string& name, Value in, int32_t cout) {
    const float std = std::sqrt(kLinearGain / static_cast<float>(in.c));
    std::vector<float> w(static_cast<size_t>(cout) * in.c), b(static_cast<size_t>(cout));
    for (float& v : w) v = std * rng_.normal();
    for (float& v : b) v = rng_.uniform(-kBiasRange, kBiasRange);
    const int32_t wt = g_.builder.add_constant<float>(name + ".weight", {cout, in.c}, w);
    const int32_t bt = g_.builder.add_constant<float>(name + ".bias", {cout}, b);
    const int32_t out = g_.builder.add_activation(name, DType::kFloat32, {1, cout});
    g_.builder.add_op(OpType::kFullyConnected, name, {in.tensor, wt, bt}, out,
                      FullyConnectedParams{});
    count(name, static_cast<uint64_t>(cout) * in.c);
    return {out, 1, 1, cout};
  }

 private:
  void count(const std::string& name, uint64_t macs) {
    g_.macs += macs;
    g_.layers.push_back({name, macs});
  }

  EncoderGraph& g_;
  Rng rng_;
};

}  // namespace

EncoderGraph build_encoder_graph(const ReferenceEncoderOptions& options) {
  EncoderGraph g;
  NetBuilder net(g, derive_seed(options.seed, 1));
  const Value image = net.input(options.resolution);
  Value x = net.conv("stem", image, kStemChannels, 3, 2, false, Activation::kRelu6, kReluGain);
  int index = 0;
  for (const Block& blk : kBlocks) {
    const std::string name = "block" + std::to_string(++index);
    const bool residual = blk.stride == 1 && blk.channels == x.c;
    Value y = x;
    if (blk.expansion != 1) {
      y = net.conv(name + ".expand", y, x.c * blk.expansion, 1, 1, false, Activation::kRelu6,
                   kReluGain);
    }
    y = net.conv(name + ".depthwise", y, y.c, 3, blk.stride, true, Activation::kRelu6, kReluGain);
    y = net.conv(name + ".project", y, blk.channels, 1, 1, false, Activation::kNone,
                 residual ? kLinearGain * kResidualGain : kLinearGain);
    x = residual ? net.add(name + ".add", x, y) : y;
  }
  x = net.conv("head", x, kHeadChannels, 1, 1, false, Activation::kRelu6, kReluGain);
  x = net.pool_and_flatten(x);
  const Value embedding = net.fully_connected("embedding", x, options.embedding_dim);
  g.builder.set_inputs({image.tensor});
  g.builder.set_outputs({embedding.tensor});
  return g;
}

}  // namespace tlvlink::quantize::encoder_internal
