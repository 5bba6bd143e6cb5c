#include "xnnpack/graphs.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace tlvlink::testing {
namespace {

size_t count(const std::vector<int32_t>& shape) {
  size_t n = 1;
  for (int32_t d : shape) n *= static_cast<size_t>(d);
  return n;
}

std::vector<int32_t> broadcast(const std::vector<int32_t>& a, const std::vector<int32_t>& b) {
  const size_t rank = std::max(a.size(), b.size());
  std::vector<int32_t> out(rank);
  for (size_t i = 0; i < rank; ++i) {
    const int32_t da = i < rank - a.size() ? 1 : a[i - (rank - a.size())];
    const int32_t db = i < rank - b.size() ? 1 : b[i - (rank - b.size())];
    out[i] = std::max(da, db);
  }
  return out;
}

// Adds a conv op reading `in` ([n,h,w,cin]) to g; returns its output.
int32_t add_conv(TGraph& g, int32_t in, const ConvCase& c, const std::string& name, Rng& rng) {
  const std::vector<int32_t> wshape = {c.cout, c.kh, c.kw, c.cin / c.groups};
  // Weights ~ U(-1,1)/sqrt(fan-in) keep activations O(1) through a chain.
  const float bound = 1.0f / std::sqrt(static_cast<float>(c.kh * c.kw * c.cin / c.groups));
  const int32_t w =
      g.constant(name + ".w", wshape, rng.floats(count(wshape), -bound, bound), TKind::kWeights);
  std::vector<int32_t> inputs = {in, w};
  if (c.bias) {
    inputs.push_back(g.constant(
        name + ".b", {c.cout}, rng.floats(static_cast<size_t>(c.cout), -0.3f, 0.3f), TKind::kBias));
  }
  Conv2DParams p;
  p.kernel_h = c.kh, p.kernel_w = c.kw;
  p.stride_h = c.stride_h, p.stride_w = c.stride_w;
  p.dilation_h = c.dilation_h, p.dilation_w = c.dilation_w;
  p.pad_top = c.pad_top, p.pad_bottom = c.pad_bottom, p.pad_left = c.pad_left,
  p.pad_right = c.pad_right;
  p.groups = c.groups;
  p.activation = c.activation;
  const int32_t oh =
      conv_output_size(c.h, c.kh, c.stride_h, c.dilation_h, c.pad_top + c.pad_bottom);
  const int32_t ow =
      conv_output_size(c.w, c.kw, c.stride_w, c.dilation_w, c.pad_left + c.pad_right);
  return g.op(OpType::kConv2D, name, inputs, {c.n, oh, ow, c.cout}, p);
}

int32_t add_fc(TGraph& g, int32_t in, int32_t n, int32_t cin, int32_t cout, bool bias,
               Activation act, const std::string& name, Rng& rng) {
  const float bound = 1.0f / std::sqrt(static_cast<float>(cin));
  const int32_t w =
      g.constant(name + ".w", {cout, cin},
                 rng.floats(static_cast<size_t>(cout * cin), -bound, bound), TKind::kWeights);
  std::vector<int32_t> inputs = {in, w};
  if (bias) {
    inputs.push_back(g.constant(name + ".b", {cout},
                                rng.floats(static_cast<size_t>(cout), -0.3f, 0.3f), TKind::kBias));
  }
  return g.op(OpType::kFullyConnected, name, inputs, {n, cout}, FullyConnectedParams{act});
}

}  // namespace

int32_t conv_output_size(int32_t in, int32_t k, int32_t stride, int32_t dilation, int32_t pad) {
  return (in + pad - ((k - 1) * dilation + 1)) / stride + 1;
}

TGraph conv_graph(const ConvCase& c, Rng& rng) {
  TGraph g;
  const int32_t in = g.activation("input", {c.n, c.h, c.w, c.cin});
  g.inputs = {in};
  g.outputs = {add_conv(g, in, c, "conv", rng)};
  return g;
}

TGraph fc_graph(int32_t n, int32_t cin, int32_t cout, bool bias, Activation act, Rng& rng) {
  TGraph g;
  const int32_t in = g.activation("input", {n, cin});
  g.inputs = {in};
  g.outputs = {add_fc(g, in, n, cin, cout, bias, act, "fc", rng)};
  return g;
}

TGraph binary_graph(OpType type, std::vector<int32_t> a_shape, std::vector<int32_t> b_shape,
                    bool b_constant, Activation act, Rng& rng) {
  TGraph g;
  const int32_t a = g.activation("a", a_shape);
  const int32_t b = b_constant ? g.constant("b", b_shape, rng.floats(count(b_shape), -1.0f, 1.0f))
                               : g.activation("b", b_shape);
  g.inputs = {a};
  if (!b_constant) g.inputs.push_back(b);
  g.outputs = {g.op(type, type == OpType::kAdd ? "add" : "mul", {a, b}, broadcast(a_shape, b_shape),
                    BinaryParams{act})};
  return g;
}

TGraph unary_graph(OpType type, std::vector<int32_t> shape, std::vector<int32_t> out_shape,
                   OpParams params) {
  TGraph g;
  const int32_t in = g.activation("input", std::move(shape));
  g.inputs = {in};
  g.outputs = {g.op(type, op_type_name(type), {in}, std::move(out_shape), params)};
  return g;
}

ConvCase random_conv_case(Rng& rng) {
  ConvCase c;
  c.n = rng.int_in(1, 2);
  c.h = rng.int_in(3, 12);
  c.w = rng.int_in(3, 12);
  c.kh = rng.int_in(1, 3) * 2 - 1;  // 1, 3, 5
  c.kw = rng.coin() ? c.kh : rng.int_in(1, 3);
  c.stride_h = rng.int_in(1, 2);
  c.stride_w = rng.int_in(1, 2);
  c.dilation_h = rng.int_in(1, 4) == 4 ? 2 : 1;
  c.dilation_w = c.dilation_h;
  c.pad_top = rng.int_in(0, c.kh / 2 + 1);
  c.pad_bottom = rng.int_in(0, c.kh / 2 + 1);
  c.pad_left = rng.int_in(0, c.kw / 2 + 1);
  c.pad_right = rng.int_in(0, c.kw / 2 + 1);
  // The padded input must hold at least one (dilated) kernel window.
  c.h = std::max(c.h, (c.kh - 1) * c.dilation_h + 1 - c.pad_top - c.pad_bottom);
  c.w = std::max(c.w, (c.kw - 1) * c.dilation_w + 1 - c.pad_left - c.pad_right);
  switch (rng.int_in(0, 2)) {
    case 0:  // dense
      c.cin = rng.int_in(1, 12);
      c.cout = rng.int_in(1, 16);
      break;
    case 1:  // depthwise, multiplier 1 or 2
      c.cin = c.groups = rng.int_in(2, 16);
      c.cout = c.cin * rng.int_in(1, 2);
      break;
    default:  // grouped
      c.groups = rng.int_in(2, 4);
      c.cin = c.groups * rng.int_in(1, 4);
      c.cout = c.groups * rng.int_in(1, 4);
      break;
  }
  c.bias = rng.int_in(0, 4) != 0;
  c.activation = static_cast<Activation>(rng.int_in(0, 2));
  return c;
}

TGraph random_chain(Rng& rng) {
  TGraph g;
  const int32_t h = rng.int_in(6, 12), w = rng.int_in(6, 12);
  const int32_t cin = rng.int_in(1, 4), c = rng.int_in(2, 12);
  const int32_t in = g.activation("input", {1, h, w, cin});
  g.inputs = {in};
  ConvCase stem;
  stem.h = h, stem.w = w, stem.cin = cin, stem.cout = c, stem.activation = Activation::kRelu;
  const int32_t x = add_conv(g, in, stem, "stem", rng);
  ConvCase dw = stem;
  dw.cin = c, dw.cout = c, dw.groups = rng.coin() ? c : 1, dw.activation = Activation::kRelu6;
  const int32_t y = add_conv(g, x, dw, "block", rng);
  int32_t z = g.op(OpType::kAdd, "residual", {x, y}, {1, h, w, c}, BinaryParams{});
  if (rng.coin()) {  // per-channel scale, broadcast along N, H, W
    const int32_t s = g.constant("scale", {c}, rng.floats(static_cast<size_t>(c), 0.5f, 1.5f));
    z = g.op(OpType::kMul, "channel_scale", {z, s}, {1, h, w, c}, BinaryParams{});
  }
  const int32_t ph = (h - 2) / 2 + 1, pw = (w - 2) / 2 + 1;
  Pool2DParams pool;
  pool.pool_h = pool.pool_w = 2;
  pool.stride_h = pool.stride_w = 2;
  z = g.op(OpType::kMaxPool2D, "pool", {z}, {1, ph, pw, c}, pool);
  z = g.op(OpType::kGlobalAveragePool, "gap", {z}, {1, 1, 1, c});
  z = g.op(OpType::kReshape, "flatten", {z}, {1, c});
  const int32_t cout = rng.int_in(1, 10);
  z = add_fc(g, z, 1, c, cout, true, Activation::kNone, "head", rng);
  if (rng.coin()) z = g.op(OpType::kSigmoid, "prob", {z}, {1, cout});
  g.outputs = {z};
  return g;
}

}  // namespace tlvlink::testing
