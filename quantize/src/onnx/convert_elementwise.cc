// Relu, Clip, Sigmoid, Add/Sub/Mul/Div. Clamps fuse into the op before them when they amount
// to ReLU or ReLU6; per-channel constant Add/Mul fold into a Conv/Gemm's bias and weights.

#include <algorithm>
#include <cfloat>
#include <limits>

#include "onnx/onnx_internal.h"

namespace tlvlink::quantize::onnx_internal {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

bool has_activation_param(OpType t) {
  return t == OpType::kConv2D || t == OpType::kFullyConnected || t == OpType::kAdd ||
         t == OpType::kMul;
}

Activation& activation_of(Node& n) {
  switch (n.type) {
    case OpType::kConv2D: return std::get<Conv2DParams>(n.params).activation;
    case OpType::kFullyConnected: return std::get<FullyConnectedParams>(n.params).activation;
    default: return std::get<BinaryParams>(n.params).activation;
  }
}

Status add_unary(Importer& imp, const onnx::NodeProto& node, int32_t x, OpType type,
                 OpParams params) {
  const Value in = imp.value(x);
  Node n;
  n.type = type;
  n.name = node_name(node);
  n.params = params;
  n.inputs = {Operand{x, {}}};
  return imp.add_node(std::move(n), node.output(0), in.shape, in.layout, in.perm).status();
}

// Clip's bounds: attributes before opset 11, optional constant inputs from 11 on. ONNX's
// "no bound" defaults (the float limits) become infinities.
Status clip_bounds(Importer& imp, const onnx::NodeProto& node, float& lo, float& hi) {
  if (imp.opset() < 11) {
    TLV_ASSIGN_OR_RETURN(lo, attr_float(node, "min", -kInf));
    TLV_ASSIGN_OR_RETURN(hi, attr_float(node, "max", kInf));
  } else {
    for (int k = 1; k <= 2; ++k) {
      if (!imp.has_input(node, k)) continue;
      TLV_ASSIGN_OR_RETURN(const Constant* c, imp.constant_input(node, k));
      TLV_ENSURE(c->elements() == 1, ErrorCode::kModelUnsupported, "%s: bound %s must be a scalar",
                 node_label(node).c_str(), dims_string(c->dims).c_str());
      (k == 1 ? lo : hi) = c->float_at(0);
    }
  }
  if (lo <= -FLT_MAX) lo = -kInf;
  if (hi >= FLT_MAX) hi = kInf;
  TLV_ENSURE(lo <= hi, ErrorCode::kModelUnsupported, "%s: min %g is above max %g",
             node_label(node).c_str(), static_cast<double>(lo), static_cast<double>(hi));
  return {};
}

}  // namespace

Status apply_clamp(Importer& imp, const onnx::NodeProto& node, int32_t x, float lo, float hi) {
  if (Node* p = imp.sole_producer(x); p != nullptr && has_activation_param(p->type)) {
    Activation& act = activation_of(*p);
    const float new_lo = std::max(lo, activation_min(act));
    const float new_hi = std::min(hi, activation_max(act));
    const bool relu = new_lo == 0.0f && new_hi == kInf;
    const bool relu6 = new_lo == 0.0f && new_hi == 6.0f;
    if (relu || relu6) {
      act = relu ? Activation::kRelu : Activation::kRelu6;
      imp.alias(node.output(0), x);
      imp.count_fused();
      return {};
    }
  }
  return add_unary(imp, node, x, OpType::kClamp, ClampParams{lo, hi});
}

Status convert_relu(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  return apply_clamp(imp, node, x, 0.0f, kInf);
}

Status convert_clip(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  float lo = -kInf, hi = kInf;
  TLV_TRY(clip_bounds(imp, node, lo, hi));
  return apply_clamp(imp, node, x, lo, hi);
}

Status convert_sigmoid(Importer& imp, const onnx::NodeProto& node) {
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, 0));
  return add_unary(imp, node, x, OpType::kSigmoid, NoParams{});
}

Status convert_binary(Importer& imp, const onnx::NodeProto& node) {
  const std::string& op = node.op_type();
  const bool additive = op == "Add" || op == "Sub";
  const OpType type = additive ? OpType::kAdd : OpType::kMul;
  TLV_ENSURE(node.input_size() == 2, ErrorCode::kFormat, "%s needs 2 inputs",
             node_label(node).c_str());
  const bool const0 = imp.is_constant(node.input(0));
  const bool const1 = imp.is_constant(node.input(1));
  if (!const0 && !const1) {
    TLV_ENSURE(op == "Add" || op == "Mul", ErrorCode::kModelUnsupported,
               "%s: %s of two activations is not supported (only with a constant operand)",
               node_label(node).c_str(), op.c_str());
    TLV_ASSIGN_OR_RETURN(const int32_t a, imp.activation_input(node, 0));
    TLV_ASSIGN_OR_RETURN(const int32_t b, imp.activation_input(node, 1));
    const Value va = imp.value(a), vb = imp.value(b);
    TLV_ASSIGN_OR_RETURN(std::vector<int64_t> shape, broadcast_dims(node, va.shape, vb.shape));
    TLV_ENSURE(va.layout == vb.layout && va.perm == vb.perm &&
                   (va.layout != Layout::kNhwc || shape.size() == 4),
               ErrorCode::kModelUnsupported,
               "%s: operands %s and %s are held in different layouts (NHWC feature map vs "
               "flat tensor)",
               node_label(node).c_str(), dims_string(va.shape).c_str(),
               dims_string(vb.shape).c_str());
    Node n;
    n.type = type;
    n.name = node_name(node);
    n.params = BinaryParams{};
    n.inputs = {Operand{a, {}}, Operand{b, {}}};
    return imp.add_node(std::move(n), node.output(0), shape, va.layout, va.perm).status();
  }

  // One constant operand: x - c = x + (-c), x / c = x * (1/c); c - x and c / x are rejected.
  TLV_ENSURE(const1 || !additive || op == "Add", ErrorCode::kModelUnsupported,
             "%s: constant - activation is not supported", node_label(node).c_str());
  TLV_ENSURE(const1 || op != "Div", ErrorCode::kModelUnsupported,
             "%s: constant / activation is not supported", node_label(node).c_str());
  const int act_index = const0 ? 1 : 0;
  TLV_ASSIGN_OR_RETURN(const int32_t x, imp.activation_input(node, act_index));
  TLV_ASSIGN_OR_RETURN(const Constant* c, imp.constant_input(node, 1 - act_index));
  Constant k = *c;
  if (!k.is_float) {
    k.f.assign(k.i.begin(), k.i.end());
    k.i.clear();
    k.is_float = true;
  }
  for (float& v : k.f) {
    if (op == "Sub") v = -v;
    if (op == "Div") {
      TLV_ENSURE(v != 0.0f, ErrorCode::kModelInvalidTensor, "%s divides by zero (constant '%s')",
                 node_label(node).c_str(), node.input(1).c_str());
      v = 1.0f / v;
    }
  }
  const Value in = imp.value(x);
  TLV_ASSIGN_OR_RETURN(std::vector<int64_t> shape, broadcast_dims(node, in.shape, k.dims));
  TLV_ASSIGN_OR_RETURN(ConstOperand operand, constant_for(node, in, k, node.input(1 - act_index)));
  if (shape == in.shape) {
    const std::vector<float> v = per_channel(operand, in);
    Node* linear = v.empty() ? nullptr : foldable_linear(imp, x);
    if (linear != nullptr) {
      if (additive) {
        fold_affine(*linear, {}, v);
      } else {
        fold_affine(*linear, v, {});
      }
      imp.alias(node.output(0), x);
      imp.count_fused();
      return {};
    }
  }
  Node n;
  n.type = type;
  n.name = node_name(node);
  n.params = BinaryParams{};
  n.inputs = {Operand{x, {}}, Operand{-1, std::move(operand)}};
  return imp.add_node(std::move(n), node.output(0), shape, in.layout, in.perm).status();
}

Status emit_affine(Importer& imp, const onnx::NodeProto& node, int32_t x, std::vector<float> a,
                   std::vector<float> b) {
  const Value in = imp.value(x);
  const auto channels = static_cast<int32_t>(in.shape[1]);
  // The per-channel constants in x's stored layout: channel is the last axis for NHWC,
  // axis 1 (logical) otherwise; a flattened map needs its features permuted.
  std::vector<int32_t> shape(in.shape.size(), 1);
  if (in.layout == Layout::kNhwc) {
    shape[3] = channels;
  } else {
    shape[1] = channels;
  }
  if (in.layout == Layout::kPermuted) {
    std::vector<float> pa(a.size()), pb(b.size());
    for (size_t j = 0; j < a.size(); ++j) {
      pa[j] = a[static_cast<size_t>(in.perm[j])];
      pb[j] = b[static_cast<size_t>(in.perm[j])];
    }
    a = std::move(pa);
    b = std::move(pb);
  }
  const std::string name = node_name(node);
  Node mul;
  mul.type = OpType::kMul;
  mul.name = name + "/scale";
  mul.params = BinaryParams{};
  mul.inputs = {Operand{x, {}}, Operand{-1, ConstOperand{name + ".scale", shape, std::move(a)}}};
  TLV_ASSIGN_OR_RETURN(const int32_t m, imp.add_node(std::move(mul), name + "/scaled", in.shape,
                                                     in.layout, in.perm));
  const int32_t scaled = imp.node(m).output;
  imp.value(scaled).uses = 1;  // read by the Add below
  Node add;
  add.type = OpType::kAdd;
  add.name = name + "/shift";
  add.params = BinaryParams{};
  add.inputs = {Operand{scaled, {}},
                Operand{-1, ConstOperand{name + ".shift", shape, std::move(b)}}};
  return imp.add_node(std::move(add), node.output(0), in.shape, in.layout, in.perm).status();
}

}  // namespace tlvlink::quantize::onnx_internal
