// Element-wise, pooling, shaping and conversion operators as XNNPACK nodes. Real-valued bounds
// (fused activations, clamp) are passed as floats: XNNPACK quantizes them on qint8 outputs.
#include "xnnpack/define_ops.h"

#include <limits>

namespace tlvlink::xnn {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

Status define_binary(ValueTable& values, const Operator& op, BinaryKind kind, const NodeRef& who) {
  const Activation act = op.get<BinaryParams>().activation;
  TLV_ASSIGN_OR_RETURN(const uint32_t a, values.value(op.inputs[0]));
  TLV_ASSIGN_OR_RETURN(const uint32_t b, values.value(op.inputs[1]));
  TLV_ASSIGN_OR_RETURN(const uint32_t out, values.value(op.output));
  return values.subgraph().define_binary(kind, activation_min(act), activation_max(act), a, b, out,
                                         who);
}

Status define_max_pool(ValueTable& values, const Operator& op, const NodeRef& who) {
  const Pool2DParams& p = op.get<Pool2DParams>();
  MaxPool2DSpec spec;
  spec.pad_top = static_cast<uint32_t>(p.pad_top);
  spec.pad_right = static_cast<uint32_t>(p.pad_right);
  spec.pad_bottom = static_cast<uint32_t>(p.pad_bottom);
  spec.pad_left = static_cast<uint32_t>(p.pad_left);
  spec.pool_h = static_cast<uint32_t>(p.pool_h);
  spec.pool_w = static_cast<uint32_t>(p.pool_w);
  spec.stride_h = static_cast<uint32_t>(p.stride_h);
  spec.stride_w = static_cast<uint32_t>(p.stride_w);
  spec.output_min = -kInf;
  spec.output_max = kInf;
  TLV_ASSIGN_OR_RETURN(spec.input, values.value(op.inputs[0]));
  TLV_ASSIGN_OR_RETURN(spec.output, values.value(op.output));
  return values.subgraph().define_max_pooling_2d(spec, who);
}

Status define_pad(ValueTable& values, const Operator& op, const NodeRef& who) {
  const PadParams& p = op.get<PadParams>();
  const size_t rank = values.graph().tensor(op.inputs[0]).shape.rank;
  Dims before, after;
  before.rank = after.rank = rank;
  for (size_t i = 0; i < rank; ++i) {
    before.d[i] = static_cast<size_t>(p.before[i]);
    after.d[i] = static_cast<size_t>(p.after[i]);
  }
  TLV_ASSIGN_OR_RETURN(const uint32_t in, values.value(op.inputs[0]));
  TLV_ASSIGN_OR_RETURN(const uint32_t out, values.value(op.output));
  return values.subgraph().define_constant_pad(before.span(), after.span(), p.value, in, out, who);
}

// Unary ops whose only parameters are the input and output values.
template <typename Fn>
Status define_unary(ValueTable& values, const Operator& op, Fn&& define) {
  TLV_ASSIGN_OR_RETURN(const uint32_t in, values.value(op.inputs[0]));
  TLV_ASSIGN_OR_RETURN(const uint32_t out, values.value(op.output));
  return define(in, out);
}

}  // namespace

Status define_operator(ValueTable& values, int32_t op_index) {
  const Graph& graph = values.graph();
  const Operator& op = graph.operators[static_cast<size_t>(op_index)];
  const NodeRef who = operator_ref(graph, op_index);
  Subgraph& sg = values.subgraph();
  switch (op.type) {
    case OpType::kConv2D: return define_conv2d(values, op_index);
    case OpType::kFullyConnected: return define_fully_connected(values, op_index);
    case OpType::kAdd: return define_binary(values, op, BinaryKind::kAdd, who);
    case OpType::kMul: return define_binary(values, op, BinaryKind::kMultiply, who);
    case OpType::kMaxPool2D: return define_max_pool(values, op, who);
    case OpType::kPad: return define_pad(values, op, who);
    case OpType::kClamp: {
      const ClampParams& p = op.get<ClampParams>();
      return define_unary(values, op, [&](uint32_t in, uint32_t out) {
        return sg.define_clamp(p.min, p.max, in, out, who);
      });
    }
    case OpType::kSigmoid:
      return define_unary(
          values, op, [&](uint32_t in, uint32_t out) { return sg.define_sigmoid(in, out, who); });
    case OpType::kGlobalAveragePool:
      return define_unary(values, op, [&](uint32_t in, uint32_t out) {
        return sg.define_global_average_pooling_2d(-kInf, kInf, in, out, who);
      });
    case OpType::kReshape: {
      const Dims dims = dims_of(graph.tensor(op.output).shape);
      return define_unary(values, op, [&](uint32_t in, uint32_t out) {
        return sg.define_reshape(dims.span(), in, out, who);
      });
    }
    case OpType::kResizeBilinear: {
      const Shape& s = graph.tensor(op.output).shape;
      const bool align = op.get<ResizeBilinearParams>().align_corners;
      return define_unary(values, op, [&](uint32_t in, uint32_t out) {
        return sg.define_resize_bilinear_2d(static_cast<size_t>(s[1]), static_cast<size_t>(s[2]),
                                            align, in, out, who);
      });
    }
    case OpType::kQuantize:
    case OpType::kDequantize:
      return define_unary(
          values, op, [&](uint32_t in, uint32_t out) { return sg.define_convert(in, out, who); });
  }
  return Error::make(
      ErrorCode::kModelUnsupported, "operator '%.*s' (#%d): type %s has no XNNPACK form",
      static_cast<int>(who.name.size()), who.name.data(), op_index, op_type_name(op.type));
}

}  // namespace tlvlink::xnn
