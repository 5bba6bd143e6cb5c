// Folded student graph for the .tlvm writer.

#include "export_graph.h"

#include <string>

namespace tlvlink::trainer {

Result<uint64_t> add_student_graph(const PlainNet& net, quantize::ModelBuilder& b) {
  const ArchSpec& a = net.arch;
  TLV_ENSURE(net.layers.size() == a.layers.size(), ErrorCode::kInvalidArgument,
             "%zu trained layers for an architecture of %zu", net.layers.size(), a.layers.size());
  int32_t h = a.input_height, w = a.input_width, c = 3;
  int32_t x = b.add_activation("input", DType::kFloat32, {1, h, w, c});
  const int32_t input = x;
  uint64_t macs = 0;
  for (size_t i = 0; i < a.layers.size(); ++i) {
    const LayerSpec& l = a.layers[i];
    const PlainLayer& p = net.layers[i];
    const std::string name = "layer" + std::to_string(i);
    TLV_ENSURE(p.shape.out_channels == l.out_channels && p.shape.in_channels == c &&
                   p.shape.kernel_h == l.kernel && p.shape.kernel_w == l.kernel,
               ErrorCode::kInvalidArgument,
               "%s: trained weights [%d, %d, %d, %d] do not fit the architecture (%d <- %d, k%d)",
               name.c_str(), p.shape.out_channels, p.shape.in_channels, p.shape.kernel_h,
               p.shape.kernel_w, l.out_channels, c, l.kernel);
    auto folded = fold_batchnorm(p.weight_oihw, p.shape, {}, p.bn);
    if (!folded.ok()) return folded.error().with_context("%s", name.c_str());
    const int32_t oh = conv_output_size(h, l.kernel, l.stride);
    const int32_t ow = conv_output_size(w, l.kernel, l.stride);
    const bool residual = l.kind == LayerKind::kResidualBnRelu6;
    const int32_t wt = b.add_constant<float>(
        name + ".weight", {l.out_channels, l.kernel, l.kernel, c}, folded->weight_ohwi);
    const int32_t bt = b.add_constant<float>(name + ".bias", {l.out_channels}, folded->bias);
    const int32_t y = b.add_activation(name + (residual ? ".conv" : ".out"), DType::kFloat32,
                                       {1, oh, ow, l.out_channels});
    Conv2DParams cp;
    cp.kernel_h = cp.kernel_w = l.kernel;
    cp.stride_h = cp.stride_w = l.stride;
    cp.pad_top = cp.pad_bottom = cp.pad_left = cp.pad_right = l.kernel / 2;
    cp.activation = residual ? Activation::kNone : Activation::kRelu6;
    b.add_op(OpType::kConv2D, name, {x, wt, bt}, y, cp);
    macs += p.shape.weights() * static_cast<uint64_t>(oh) * static_cast<uint64_t>(ow);
    if (residual) {
      const int32_t sum =
          b.add_activation(name + ".out", DType::kFloat32, {1, oh, ow, l.out_channels});
      b.add_op(OpType::kAdd, name + ".add", {x, y}, sum, BinaryParams{Activation::kRelu6});
      x = sum;
    } else {
      x = y;
    }
    h = oh;
    w = ow;
    c = l.out_channels;
  }
  const int32_t pooled = b.add_activation("pool.out", DType::kFloat32, {1, 1, 1, c});
  b.add_op(OpType::kGlobalAveragePool, "pool", {x}, pooled);
  const int32_t flat = b.add_activation("flatten.out", DType::kFloat32, {1, c});
  b.add_op(OpType::kReshape, "flatten", {pooled}, flat);
  const int32_t d = a.embedding_dim;
  TLV_ENSURE(net.fc_weight.size() == static_cast<size_t>(d) * static_cast<size_t>(c) &&
                 net.fc_bias.size() == static_cast<size_t>(d),
             ErrorCode::kInvalidArgument, "embedding FC holds %zu/%zu values for [%d, %d]",
             net.fc_weight.size(), net.fc_bias.size(), d, c);
  const int32_t fw = b.add_constant<float>("embedding.weight", {d, c}, net.fc_weight);
  const int32_t fb = b.add_constant<float>("embedding.bias", {d}, net.fc_bias);
  const int32_t out = b.add_activation("embedding", DType::kFloat32, {1, d});
  b.add_op(OpType::kFullyConnected, "embedding", {flat, fw, fb}, out, FullyConnectedParams{});
  macs += static_cast<uint64_t>(d) * static_cast<uint64_t>(c);
  b.set_inputs({input});
  b.set_outputs({out});
  return macs;
}

}  // namespace tlvlink::trainer
