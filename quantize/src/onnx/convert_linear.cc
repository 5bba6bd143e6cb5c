// Conv, Gemm, MatMul (constant weights) and BatchNormalization. Weights move from OIHW to OHWI;
// BatchNorm folds into the Conv/Gemm before it, or becomes Mul + Add on an activation.

#include <cmath>

#include "onnx/onnx_internal.h"

namespace tlvlink::quantize::onnx_internal {
namespace {

constexpr int64_t kOihwToOhwi[4] = {0, 2, 3, 1};

Activation fused_activation(const Node& n) {
  if (n.type == OpType::kConv2D) return n.get<Conv2DParams>().activation;
  return n.get<FullyConnectedParams>().activation;
}

// A bias [cout] from input 2 of a Conv (1-D) or Gemm (broadcast to [1, cout], times beta).
Result<ConstOperand> read_bias(Importer& imp, const onnx::NodeProto& node, int64_t cout,
                               float beta) {
  ConstOperand bias{node_name(node) + ".bias",
                    {static_cast<int32_t>(cout)},
                    std::vector<float>(static_cast<size_t>(cout), 0.0f)};
  if (!imp.has_input(node, 2)) return bias;
  TLV_ASSIGN_OR_RETURN(const Constant* c, imp.constant_input(node, 2));
  const int64_t n = static_cast<int64_t>(c->elements());
  TLV_ENSURE(c->is_float && (n == cout || n == 1) && c->dims.size() <= 2 &&
                 (c->dims.empty() || c->dims.back() == n),
             ErrorCode::kModelUnsupported,
             "%s: bias %s does not broadcast per output channel (%lld)", node_label(node).c_str(),
             dims_string(c->dims).c_str(), static_cast<long long>(cout));
  bias.name = node.input(2);
  for (size_t k = 0; k < bias.data.size(); ++k) bias.data[k] = beta * c->f[n == 1 ? 0 : k];
  return bias;
}

// FullyConnected y = x W^T + b for a 2-D activation; `w` is [cout, k] in logical feature order
// and is permuted here when x is a flattened NCHW map stored in NHWC order.
Status add_fully_connected(Importer& imp, const onnx::NodeProto& node, int32_t x,
                           std::string w_name, std::vector<float> w, int64_t cout,
                           ConstOperand bias) {
  const Value in = imp.value(x);
  const int64_t k = in.shape[1];
  if (in.layout == Layout::kPermuted) {
    std::vector<float> permuted(w.size());
    for (int64_t o = 0; o < cout; ++o) {
      for (int64_t j = 0; j < k; ++j) {
        permuted[static_cast<size_t>(o * k + j)] =
            w[static_cast<size_t>(o * k + in.perm[static_cast<size_t>(j)])];
      }
    }
    w = std::move(permuted);
  }
  Node n;
  n.type = OpType::kFullyConnected;
  n.name = node_name(node);
  n.params = FullyConnectedParams{};
  n.inputs = {Operand{x, {}},
              Operand{-1, ConstOperand{std::move(w_name),
                                       {static_cast<int32_t>(cout), static_cast<int32_t>(k)},
                                       std::move(w)}},
              Operand{-1, std::move(bias)}};
  return imp.add_node(std::move(n), node.output(0), {in.shape[0], cout}, Layout::kPlain).status();
}

Status check_matrix_input(const onnx::NodeProto& node, const Value& in) {
  TLV_ENSURE(in.shape.size() == 2, ErrorCode::kModelUnsupported,
             "%s: input '%s' is %s; tlvlink's fully-connected op takes a 2-D [N, K] input "
             "(flatten first)",
             node_label(node).c_str(), in.name.c_str(), dims_string(in.shape).c_str());
  return {};
}

}  // namespace

Node* foldable_linear(Importer& imp, int32_t v) {
  Node* n = imp.sole_producer(v);
  if (n == nullptr || (n->type != OpType::kConv2D && n->type != OpType::kFullyConnected)) {
    return nullptr;
  }
  return fused_activation(*n) == Activation::kNone ? n : nullptr;
}

void fold_affine(Node& linear, std::span<const float> a, std::span<const float> b) {
  std::vector<float>& w = linear.inputs[1].constant.data;
  std::vector<float>& bias = linear.inputs[2].constant.data;
  const size_t cout = bias.size();
  const size_t per_channel = w.size() / cout;
  for (size_t c = 0; c < cout; ++c) {
    const float scale = a.empty() ? 1.0f : a[c];
    for (size_t i = 0; i < per_channel; ++i) w[c * per_channel + i] *= scale;
    bias[c] = bias[c] * scale + (b.empty() ? 0.0f : b[c]);
  }
}

Status convert_conv(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  TLV_ASSIGN_OR_RETURN(const Constant* w, imp.constant_input(node, 1));
  const Value in = imp.value(x);
  TLV_ENSURE(in.layout == Layout::kNhwc, ErrorCode::kModelUnsupported,
             "%s: input '%s' is %s; only 2-D convolutions over [N, C, H, W] are supported",
             node_label(node).c_str(), in.name.c_str(), dims_string(in.shape).c_str());
  TLV_ENSURE(w->is_float && w->dims.size() == 4, ErrorCode::kModelUnsupported,
             "%s: weights %s must be float [M, C/group, kH, kW]", node_label(node).c_str(),
             dims_string(w->dims).c_str());
  TLV_ASSIGN_OR_RETURN(const int64_t group, attr_int(node, "group", 1));
  const int64_t cout = w->dims[0];
  TLV_ENSURE(
      group >= 1 && group <= in.shape[1] && in.shape[1] == w->dims[1] * group && cout % group == 0,
      ErrorCode::kModelInvalidOperator, "%s: weights %s with group %lld do not fit input %s",
      node_label(node).c_str(), dims_string(w->dims).c_str(), static_cast<long long>(group),
      dims_string(in.shape).c_str());
  TLV_ASSIGN_OR_RETURN(const std::vector<int64_t> kernel_shape, attr_ints(node, "kernel_shape"));
  const std::vector<int64_t> kernel = {w->dims[2], w->dims[3]};
  TLV_ENSURE(kernel_shape.empty() || kernel_shape == kernel, ErrorCode::kModelInvalidOperator,
             "%s: kernel_shape %s differs from the weights %s", node_label(node).c_str(),
             dims_string(kernel_shape).c_str(), dims_string(w->dims).c_str());
  std::string auto_pad;
  TLV_ASSIGN_OR_RETURN(Windows win, read_windows(node, kernel, &auto_pad));
  TLV_ASSIGN_OR_RETURN(const int64_t oh, window_output(node, in.shape[2], win[0], auto_pad));
  TLV_ASSIGN_OR_RETURN(const int64_t ow, window_output(node, in.shape[3], win[1], auto_pad));
  TLV_ASSIGN_OR_RETURN(ConstOperand bias, read_bias(imp, node, cout, 1.0f));

  Conv2DParams p;
  p.kernel_h = static_cast<int32_t>(kernel[0]);
  p.kernel_w = static_cast<int32_t>(kernel[1]);
  p.stride_h = static_cast<int32_t>(win[0].stride);
  p.stride_w = static_cast<int32_t>(win[1].stride);
  p.dilation_h = static_cast<int32_t>(win[0].dilation);
  p.dilation_w = static_cast<int32_t>(win[1].dilation);
  p.pad_top = static_cast<int32_t>(win[0].pad_begin);
  p.pad_bottom = static_cast<int32_t>(win[0].pad_end);
  p.pad_left = static_cast<int32_t>(win[1].pad_begin);
  p.pad_right = static_cast<int32_t>(win[1].pad_end);
  p.groups = static_cast<int32_t>(group);

  // A zero spatial Pad read only by this conv becomes the conv's own padding.
  int32_t source = x;
  if (Node* pad = imp.sole_producer(x); pad != nullptr && pad->type == OpType::kPad) {
    const PadParams& pp = pad->get<PadParams>();  // NHWC
    if (pp.value == 0.0f && pp.before[0] == 0 && pp.after[0] == 0 && pp.before[3] == 0 &&
        pp.after[3] == 0) {
      p.pad_top += pp.before[1];
      p.pad_bottom += pp.after[1];
      p.pad_left += pp.before[2];
      p.pad_right += pp.after[2];
      source = pad->inputs[0].value;
      pad->removed = true;
      imp.count_fused();
    }
  }
  Node n;
  n.type = OpType::kConv2D;
  n.name = node_name(node);
  n.params = p;
  ConstOperand weights{node.input(1),
                       {static_cast<int32_t>(cout), static_cast<int32_t>(kernel[0]),
                        static_cast<int32_t>(kernel[1]), static_cast<int32_t>(w->dims[1])},
                       transpose<float>(w->f, w->dims, kOihwToOhwi)};
  n.inputs = {Operand{source, {}}, Operand{-1, std::move(weights)}, Operand{-1, std::move(bias)}};
  return imp.add_node(std::move(n), node.output(0), {1, cout, oh, ow}, Layout::kNhwc).status();
}

Status convert_gemm(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  TLV_ASSIGN_OR_RETURN(const Constant* b, imp.constant_input(node, 1));
  TLV_ASSIGN_OR_RETURN(const int64_t trans_a, attr_int(node, "transA", 0));
  TLV_ASSIGN_OR_RETURN(const int64_t trans_b, attr_int(node, "transB", 0));
  TLV_ASSIGN_OR_RETURN(const float alpha, attr_float(node, "alpha", 1.0f));
  TLV_ASSIGN_OR_RETURN(const float beta, attr_float(node, "beta", 1.0f));
  const Value in = imp.value(x);
  TLV_ENSURE(trans_a == 0, ErrorCode::kModelUnsupported,
             "%s: transA=1 (a transposed activation) is not supported", node_label(node).c_str());
  TLV_TRY(check_matrix_input(node, in));
  TLV_ENSURE(b->is_float && b->dims.size() == 2, ErrorCode::kModelUnsupported,
             "%s: B %s must be a float matrix", node_label(node).c_str(),
             dims_string(b->dims).c_str());
  const int64_t k = in.shape[1];
  const int64_t cout = trans_b ? b->dims[0] : b->dims[1];
  TLV_ENSURE((trans_b ? b->dims[1] : b->dims[0]) == k, ErrorCode::kModelInvalidOperator,
             "%s: B %s (transB=%lld) does not fit input %s", node_label(node).c_str(),
             dims_string(b->dims).c_str(), static_cast<long long>(trans_b),
             dims_string(in.shape).c_str());
  std::vector<float> w(static_cast<size_t>(cout * k));
  for (int64_t o = 0; o < cout; ++o) {
    for (int64_t j = 0; j < k; ++j) {
      const size_t src = static_cast<size_t>(trans_b ? o * k + j : j * cout + o);
      w[static_cast<size_t>(o * k + j)] = alpha * b->f[src];
    }
  }
  TLV_ASSIGN_OR_RETURN(ConstOperand bias, read_bias(imp, node, cout, beta));
  return add_fully_connected(imp, node, x, node.input(1), std::move(w), cout, std::move(bias));
}

Status convert_matmul(Importer& imp, const onnx::NodeProto& node) {
  TLV_ENSURE(!imp.is_constant(node.input(0)), ErrorCode::kModelUnsupported,
             "%s: constant x activation is not supported (only activation x constant)",
             node_label(node).c_str());
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  TLV_ASSIGN_OR_RETURN(const Constant* b, imp.constant_input(node, 1));
  const Value in = imp.value(x);
  TLV_TRY(check_matrix_input(node, in));
  TLV_ENSURE(b->is_float && b->dims.size() == 2 && b->dims[0] == in.shape[1],
             ErrorCode::kModelUnsupported, "%s: B %s must be a float [%lld, N] matrix",
             node_label(node).c_str(), dims_string(b->dims).c_str(),
             static_cast<long long>(in.shape[1]));
  const int64_t cout = b->dims[1];
  const int64_t to_rows[2] = {1, 0};
  std::vector<float> w = transpose<float>(b->f, b->dims, to_rows);
  ConstOperand bias{node_name(node) + ".bias",
                    {static_cast<int32_t>(cout)},
                    std::vector<float>(static_cast<size_t>(cout), 0.0f)};
  return add_fully_connected(imp, node, x, node.input(1), std::move(w), cout, std::move(bias));
}

Status convert_batch_norm(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  const Constant* params[4];  // scale, B, mean, var
  for (int k = 0; k < 4; ++k) {
    TLV_ASSIGN_OR_RETURN(params[k], imp.constant_input(node, k + 1));
  }
  TLV_ASSIGN_OR_RETURN(const float epsilon, attr_float(node, "epsilon", 1e-5f));
  TLV_ASSIGN_OR_RETURN(const int64_t training, attr_int(node, "training_mode", 0));
  TLV_ASSIGN_OR_RETURN(const int64_t spatial, attr_int(node, "spatial", 1));
  TLV_ENSURE(training == 0, ErrorCode::kModelUnsupported,
             "%s: training_mode=1; export the model in eval mode", node_label(node).c_str());
  TLV_ENSURE(spatial == 1, ErrorCode::kModelUnsupported, "%s: spatial=0 is not supported",
             node_label(node).c_str());
  const Value in = imp.value(x);
  TLV_ENSURE(in.shape.size() >= 2, ErrorCode::kModelUnsupported, "%s: input %s has no channels",
             node_label(node).c_str(), dims_string(in.shape).c_str());
  const int64_t channels = in.shape[1];
  for (const Constant* c : params) {
    TLV_ENSURE(c->is_float && c->dims.size() == 1 && c->dims[0] == channels,
               ErrorCode::kModelInvalidOperator, "%s: parameters must be float [%lld], got %s",
               node_label(node).c_str(), static_cast<long long>(channels),
               dims_string(c->dims).c_str());
  }
  // y = a * x + b with a = scale / sqrt(var + eps), b = B - mean * a (computed in double).
  std::vector<float> a(static_cast<size_t>(channels)), b(a.size());
  for (size_t c = 0; c < a.size(); ++c) {
    const double var = static_cast<double>(params[3]->f[c]) + static_cast<double>(epsilon);
    TLV_ENSURE(var > 0.0, ErrorCode::kModelInvalidTensor,
               "%s: variance + epsilon of channel %zu is %g", node_label(node).c_str(), c, var);
    const double scale = static_cast<double>(params[0]->f[c]) / std::sqrt(var);
    a[c] = static_cast<float>(scale);
    b[c] = static_cast<float>(static_cast<double>(params[1]->f[c]) -
                              static_cast<double>(params[2]->f[c]) * scale);
  }
  if (Node* linear = foldable_linear(imp, x); linear != nullptr) {
    fold_affine(*linear, a, b);
    imp.alias(node.output(0), x);
    imp.count_fused();
    return {};
  }
  return emit_affine(imp, node, x, std::move(a), std::move(b));
}

}  // namespace tlvlink::quantize::onnx_internal
