// GlobalAveragePool (and ReduceMean over H, W), MaxPool, Flatten/Reshape/Squeeze/Unsqueeze, Pad,
// Identity/Dropout. Feature maps are stored NHWC, so reshapes are only free when NHWC and NCHW
// order agree (C == 1 or H*W == 1); a flatten of a full [1, C, H, W] map is kept as a feature
// permutation that the next Gemm/MatMul absorbs into its weights.

#include <algorithm>

#include "onnx/onnx_internal.h"

namespace tlvlink::quantize::onnx_internal {
namespace {

Result<int32_t> feature_map_input(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  const Value& in = imp.value(x);
  TLV_ENSURE(in.layout == Layout::kNhwc, ErrorCode::kModelUnsupported,
             "%s: input '%s' is %s; a 4-D [N, C, H, W] feature map is needed",
             node_label(node).c_str(), in.name.c_str(), dims_string(in.shape).c_str());
  return x;
}

Status reshape_to(Importer& imp, const onnx::NodeProto& node, int32_t x, std::vector<int64_t> out) {
  const Value in = imp.value(x);
  Layout layout = out.size() == 4 ? Layout::kNhwc : Layout::kPlain;
  std::vector<int64_t> perm;
  const bool out_logical = layout != Layout::kNhwc || out[1] == 1 || out[2] * out[3] == 1;
  if (memory_is_logical(in) && out_logical) {
    // The stored bytes are already in the order the new shape needs.
  } else if (in.layout == Layout::kNhwc && out.size() == 2 && out[0] == in.shape[0]) {
    // Flatten of [1, C, H, W]: stored (h, w, c) holds logical feature c*H*W + h*W + w.
    const int64_t c_n = in.shape[1], h_n = in.shape[2], w_n = in.shape[3];
    layout = Layout::kPermuted;
    perm.reserve(static_cast<size_t>(c_n * h_n * w_n));
    for (int64_t h = 0; h < h_n; ++h) {
      for (int64_t w = 0; w < w_n; ++w) {
        for (int64_t c = 0; c < c_n; ++c) perm.push_back(c * h_n * w_n + h * w_n + w);
      }
    }
  } else {
    return node_error(ErrorCode::kModelUnsupported, node,
                      "%s -> %s would need an NCHW/NHWC transpose, which tlvlink has no op for",
                      dims_string(in.shape).c_str(), dims_string(out).c_str());
  }
  Value probe;
  probe.shape = out;
  probe.layout = layout;
  if (stored_shape(probe) == stored_shape(in) && layout == in.layout && perm == in.perm) {
    imp.alias(node.output(0), x);  // nothing to do
    return {};
  }
  Node n;
  n.type = OpType::kReshape;
  n.name = node_name(node);
  n.inputs = {Operand{x, {}}};
  return imp.add_node(std::move(n), node.output(0), std::move(out), layout, std::move(perm))
      .status();
}

}  // namespace

Status convert_global_average_pool(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, feature_map_input(imp, node));
  const std::vector<int64_t> shape = {1, imp.value(x).shape[1], 1, 1};
  Node n;
  n.type = OpType::kGlobalAveragePool;
  n.name = node_name(node);
  n.inputs = {Operand{x, {}}};
  return imp.add_node(std::move(n), node.output(0), shape, Layout::kNhwc).status();
}

Status convert_reduce_mean(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, feature_map_input(imp, node));
  std::vector<int64_t> axes;
  if (imp.opset() < 18) {
    TLV_ASSIGN_OR_RETURN(axes, attr_ints(node, "axes"));
  } else if (imp.has_input(node, 1)) {
    TLV_ASSIGN_OR_RETURN(const Constant* a, imp.constant_input(node, 1));
    for (size_t k = 0; k < a->elements(); ++k) axes.push_back(a->int_at(k));
  }
  for (int64_t& a : axes) a = a < 0 ? a + 4 : a;
  std::sort(axes.begin(), axes.end());
  TLV_ENSURE(axes == (std::vector<int64_t>{2, 3}), ErrorCode::kModelUnsupported,
             "%s: only the mean over height and width (axes 2, 3) is supported, got %s",
             node_label(node).c_str(), dims_string(axes).c_str());
  TLV_ASSIGN_OR_RETURN(const int64_t keepdims, attr_int(node, "keepdims", 1));
  const int64_t channels = imp.value(x).shape[1];
  Node gap;
  gap.type = OpType::kGlobalAveragePool;
  gap.name = node_name(node);
  gap.inputs = {Operand{x, {}}};
  const std::string pooled = keepdims ? node.output(0) : node.output(0) + "/pooled";
  TLV_ASSIGN_OR_RETURN(const int32_t n,
                       imp.add_node(std::move(gap), pooled, {1, channels, 1, 1}, Layout::kNhwc));
  if (keepdims) return {};
  const int32_t v = imp.node(n).output;
  imp.value(v).uses = 1;  // read by the reshape below
  return reshape_to(imp, node, v, {1, channels});
}

Status convert_max_pool(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, feature_map_input(imp, node));
  const Value in = imp.value(x);
  TLV_ASSIGN_OR_RETURN(const std::vector<int64_t> kernel, attr_ints(node, "kernel_shape"));
  TLV_ASSIGN_OR_RETURN(const int64_t ceil_mode, attr_int(node, "ceil_mode", 0));
  std::string auto_pad;
  TLV_ASSIGN_OR_RETURN(Windows win, read_windows(node, kernel, &auto_pad));
  int64_t out[2];
  for (size_t k = 0; k < 2; ++k) {
    TLV_ASSIGN_OR_RETURN(out[k], window_output(node, in.shape[k + 2], win[k], auto_pad));
    const Window& w = win[k];
    TLV_ENSURE(w.dilation == 1, ErrorCode::kModelUnsupported,
               "%s: dilated max pooling is not supported", node_label(node).c_str());
    // tlvlink pools in floor mode; ceil mode is fine when it yields the same size.
    const int64_t rest = (in.shape[k + 2] + w.pad_begin + w.pad_end - w.kernel) % w.stride;
    TLV_ENSURE(ceil_mode == 0 || rest == 0, ErrorCode::kModelUnsupported,
               "%s: ceil_mode=1 adds an output row/column here; tlvlink pools in floor mode",
               node_label(node).c_str());
    // Padding never wins a max when every window overlaps the input (pads < kernel).
    TLV_ENSURE(w.pad_begin < w.kernel && w.pad_end < w.kernel, ErrorCode::kModelUnsupported,
               "%s: pads as large as the kernel are not supported", node_label(node).c_str());
  }
  Pool2DParams p;
  p.pool_h = static_cast<int32_t>(win[0].kernel);
  p.pool_w = static_cast<int32_t>(win[1].kernel);
  p.stride_h = static_cast<int32_t>(win[0].stride);
  p.stride_w = static_cast<int32_t>(win[1].stride);
  p.pad_top = static_cast<int32_t>(win[0].pad_begin);
  p.pad_bottom = static_cast<int32_t>(win[0].pad_end);
  p.pad_left = static_cast<int32_t>(win[1].pad_begin);
  p.pad_right = static_cast<int32_t>(win[1].pad_end);
  Node n;
  n.type = OpType::kMaxPool2D;
  n.name = node_name(node);
  n.params = p;
  n.inputs = {Operand{x, {}}};
  return imp.add_node(std::move(n), node.output(0), {1, in.shape[1], out[0], out[1]}, Layout::kNhwc)
      .status();
}

Status convert_flatten(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  const std::vector<int64_t> s = imp.value(x).shape;
  TLV_ASSIGN_OR_RETURN(int64_t axis, attr_int(node, "axis", 1));
  const auto rank = static_cast<int64_t>(s.size());
  if (axis < 0) axis += rank;
  TLV_ENSURE(axis >= 0 && axis <= rank, ErrorCode::kModelInvalidOperator, "%s: axis %lld for %s",
             node_label(node).c_str(), static_cast<long long>(axis), dims_string(s).c_str());
  std::vector<int64_t> out = {1, 1};
  for (int64_t k = 0; k < rank; ++k) out[k < axis ? 0 : 1] *= s[static_cast<size_t>(k)];
  return reshape_to(imp, node, x, std::move(out));
}

Status convert_reshape(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  TLV_ENSURE(imp.opset() >= 5, ErrorCode::kModelUnsupported,
             "%s: Reshape before opset 5 (shape attribute) is not supported",
             node_label(node).c_str());
  TLV_ASSIGN_OR_RETURN(const Constant* shape, imp.constant_input(node, 1));
  TLV_ASSIGN_OR_RETURN(const int64_t allowzero, attr_int(node, "allowzero", 0));
  TLV_ASSIGN_OR_RETURN(std::vector<int64_t> out,
                       reshape_target(node, imp.value(x).shape, *shape, allowzero != 0));
  return reshape_to(imp, node, x, std::move(out));
}

Status convert_squeeze(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  const std::vector<int64_t> in = imp.value(x).shape;
  std::vector<int64_t> axes;
  if (imp.opset() < 13) {
    TLV_ASSIGN_OR_RETURN(axes, attr_ints(node, "axes"));
  } else if (imp.has_input(node, 1)) {
    TLV_ASSIGN_OR_RETURN(const Constant* a, imp.constant_input(node, 1));
    for (size_t k = 0; k < a->elements(); ++k) axes.push_back(a->int_at(k));
  }
  const bool unsqueeze = node.op_type() == "Unsqueeze";
  const auto rank = static_cast<int64_t>(in.size() + (unsqueeze ? axes.size() : 0));
  std::vector<bool> listed(static_cast<size_t>(rank), false);
  for (int64_t a : axes) {
    const int64_t k = a < 0 ? a + rank : a;
    TLV_ENSURE(k >= 0 && k < rank, ErrorCode::kModelInvalidOperator, "%s: axis %lld out of range",
               node_label(node).c_str(), static_cast<long long>(a));
    listed[static_cast<size_t>(k)] = true;
  }
  std::vector<int64_t> out;
  size_t next = 0;
  for (int64_t k = 0; k < rank; ++k) {
    const bool here = listed[static_cast<size_t>(k)];
    if (unsqueeze) {
      out.push_back(here ? 1 : in[next++]);
      continue;
    }
    const int64_t d = in[static_cast<size_t>(k)];
    TLV_ENSURE(!here || d == 1, ErrorCode::kModelInvalidOperator,
               "%s: dimension %lld is %lld, not 1", node_label(node).c_str(),
               static_cast<long long>(k), static_cast<long long>(d));
    if (!here && !(axes.empty() && d == 1)) out.push_back(d);
  }
  return reshape_to(imp, node, x, std::move(out));
}

Status convert_pad(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  const Value in = imp.value(x);
  const size_t rank = in.shape.size();
  TLV_ASSIGN_OR_RETURN(const std::string mode, attr_string(node, "mode", "constant"));
  TLV_ENSURE(mode == "constant", ErrorCode::kModelUnsupported,
             "%s: mode '%s' is not supported (constant padding only)", node_label(node).c_str(),
             mode.c_str());
  std::vector<int64_t> pads;
  float value = 0.0f;
  std::vector<int64_t> axes;
  if (imp.opset() < 11) {
    TLV_ASSIGN_OR_RETURN(pads, attr_ints(node, "pads"));
    TLV_ASSIGN_OR_RETURN(value, attr_float(node, "value", 0.0f));
  } else {
    TLV_ASSIGN_OR_RETURN(const Constant* p, imp.constant_input(node, 1));
    pads = p->is_float ? std::vector<int64_t>() : p->i;
    if (imp.has_input(node, 2)) {
      TLV_ASSIGN_OR_RETURN(const Constant* v, imp.constant_input(node, 2));
      TLV_ENSURE(v->elements() == 1, ErrorCode::kModelUnsupported,
                 "%s: constant_value must be a scalar", node_label(node).c_str());
      value = v->float_at(0);
    }
    if (imp.has_input(node, 3)) {
      TLV_ASSIGN_OR_RETURN(const Constant* a, imp.constant_input(node, 3));
      for (size_t k = 0; k < a->elements(); ++k) {
        const int64_t axis = a->int_at(k);
        axes.push_back(axis < 0 ? axis + static_cast<int64_t>(rank) : axis);
      }
    }
  }
  if (axes.empty()) {
    for (size_t k = 0; k < rank; ++k) axes.push_back(static_cast<int64_t>(k));
  }
  TLV_ENSURE(pads.size() == 2 * axes.size(), ErrorCode::kModelInvalidOperator,
             "%s: pads %s do not match rank %zu", node_label(node).c_str(),
             dims_string(pads).c_str(), rank);
  std::vector<int64_t> before(rank, 0), after(rank, 0);
  for (size_t k = 0; k < axes.size(); ++k) {
    TLV_ENSURE(axes[k] >= 0 && axes[k] < static_cast<int64_t>(rank),
               ErrorCode::kModelInvalidOperator, "%s: axis %lld out of range",
               node_label(node).c_str(), static_cast<long long>(axes[k]));
    before[static_cast<size_t>(axes[k])] = pads[k];
    after[static_cast<size_t>(axes[k])] = pads[k + axes.size()];
  }
  std::vector<int64_t> shape = in.shape;
  bool any = false;
  for (size_t k = 0; k < rank; ++k) {
    TLV_ENSURE(before[k] >= 0 && after[k] >= 0 && before[k] <= 65536 && after[k] <= 65536,
               ErrorCode::kModelUnsupported, "%s: pads %s crop or are too large",
               node_label(node).c_str(), dims_string(pads).c_str());
    shape[k] += before[k] + after[k];
    any = any || before[k] != 0 || after[k] != 0;
  }
  if (!any) {
    imp.alias(node.output(0), x);
    return {};
  }
  TLV_ENSURE(before[0] == 0 && after[0] == 0, ErrorCode::kModelUnsupported,
             "%s pads the batch dimension", node_label(node).c_str());
  TLV_ENSURE(in.layout != Layout::kPermuted, ErrorCode::kModelUnsupported,
             "%s pads a flattened NCHW feature map", node_label(node).c_str());
  PadParams p;
  p.value = value;
  for (size_t k = 0; k < rank; ++k) {
    // NHWC position of logical axis k (N, C, H, W -> 0, 3, 1, 2).
    const size_t s = in.layout == Layout::kNhwc ? (k == 0 ? 0 : k == 1 ? 3 : k - 1) : k;
    p.before[s] = static_cast<int32_t>(before[k]);
    p.after[s] = static_cast<int32_t>(after[k]);
  }
  Node n;
  n.type = OpType::kPad;
  n.name = node_name(node);
  n.params = p;
  n.inputs = {Operand{x, {}}};
  return imp.add_node(std::move(n), node.output(0), std::move(shape), in.layout).status();
}

Status convert_identity(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  if (node.op_type() == "Dropout" && imp.has_input(node, 2)) {
    TLV_ASSIGN_OR_RETURN(const Constant* training, imp.constant_input(node, 2));
    TLV_ENSURE(training->elements() == 1 && training->int_at(0) == 0, ErrorCode::kModelUnsupported,
               "%s runs in training mode", node_label(node).c_str());
  }
  imp.alias(node.output(0), x);
  return {};
}

}  // namespace tlvlink::quantize::onnx_internal
