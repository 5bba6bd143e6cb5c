// Operators: type, tensor indices and options, converted into OpParams with range checks.
// Shape/dtype semantics are checked afterwards by the validate_* files.

#include <cmath>

#include "model_internal.h"
#include "tlvlink/model.h"

namespace tlvlink::model_internal {
namespace {

constexpr int32_t kMaxKernel = 1 << 12;  // generous; real tactile encoders use <= 7

struct Arity {
  size_t min_inputs, max_inputs;
};
Arity arity(OpType t) {
  switch (t) {
    case OpType::kConv2D:
    case OpType::kFullyConnected: return {2, 3};
    case OpType::kAdd:
    case OpType::kMul: return {2, 2};
    default: return {1, 1};
  }
}

Result<Activation> convert_activation(fb::Activation a, const Label& who) {
  const int v = static_cast<int>(a);
  TLV_ENSURE(v >= 0 && v <= 2, ErrorCode::kModelInvalidOperator,
             "%s has unknown fused activation %d", who.text, v);
  return static_cast<Activation>(v);
}

bool in_range(int32_t v, int32_t lo, int32_t hi) { return v >= lo && v <= hi; }

Result<OpParams> convert_params(const fb::Operator& op, OpType type, const Graph& graph,
                                const Label& who) {
  const auto opt = op.options_type();
  auto wrong_options = [&]() {
    return Error::make(ErrorCode::kModelInvalidOperator, "%s has options of type %s", who.text,
                       fb::EnumNameOpOptions(opt));
  };
  switch (type) {
    case OpType::kConv2D: {
      const auto* o = op.options_as_Conv2DOptions();
      if (o == nullptr) return wrong_options();
      Conv2DParams p;
      p.kernel_h = o->kernel_h();
      p.kernel_w = o->kernel_w();
      p.stride_h = o->stride_h();
      p.stride_w = o->stride_w();
      p.dilation_h = o->dilation_h();
      p.dilation_w = o->dilation_w();
      p.pad_top = o->pad_top();
      p.pad_bottom = o->pad_bottom();
      p.pad_left = o->pad_left();
      p.pad_right = o->pad_right();
      p.groups = o->groups();
      TLV_ENSURE(in_range(p.kernel_h, 1, kMaxKernel) && in_range(p.kernel_w, 1, kMaxKernel) &&
                     in_range(p.stride_h, 1, kMaxKernel) && in_range(p.stride_w, 1, kMaxKernel) &&
                     in_range(p.dilation_h, 1, kMaxKernel) && in_range(p.dilation_w, 1, kMaxKernel),
                 ErrorCode::kModelInvalidOperator,
                 "%s kernel %dx%d stride %dx%d dilation %dx%d: each must be in [1, %d]", who.text,
                 p.kernel_h, p.kernel_w, p.stride_h, p.stride_w, p.dilation_h, p.dilation_w,
                 kMaxKernel);
      TLV_ENSURE(in_range(p.pad_top, 0, kMaxKernel) && in_range(p.pad_bottom, 0, kMaxKernel) &&
                     in_range(p.pad_left, 0, kMaxKernel) && in_range(p.pad_right, 0, kMaxKernel),
                 ErrorCode::kModelInvalidOperator, "%s padding %d,%d,%d,%d must be in [0, %d]",
                 who.text, p.pad_top, p.pad_bottom, p.pad_left, p.pad_right, kMaxKernel);
      TLV_ENSURE(p.groups >= 1, ErrorCode::kModelInvalidOperator, "%s groups is %d", who.text,
                 p.groups);
      TLV_ASSIGN_OR_RETURN(p.activation, convert_activation(o->activation(), who));
      return OpParams{p};
    }
    case OpType::kFullyConnected: {
      FullyConnectedParams p;
      if (opt != fb::OpOptions::NONE) {
        const auto* o = op.options_as_FullyConnectedOptions();
        if (o == nullptr) return wrong_options();
        TLV_ASSIGN_OR_RETURN(p.activation, convert_activation(o->activation(), who));
      }
      return OpParams{p};
    }
    case OpType::kAdd:
    case OpType::kMul: {
      BinaryParams p;
      if (opt != fb::OpOptions::NONE) {
        const auto* o = op.options_as_BinaryOptions();
        if (o == nullptr) return wrong_options();
        TLV_ASSIGN_OR_RETURN(p.activation, convert_activation(o->activation(), who));
      }
      return OpParams{p};
    }
    case OpType::kClamp: {
      const auto* o = op.options_as_ClampOptions();
      if (o == nullptr) return wrong_options();
      TLV_ENSURE(!std::isnan(o->min()) && !std::isnan(o->max()) && o->min() <= o->max(),
                 ErrorCode::kModelInvalidOperator, "%s clamp range [%g, %g] is empty or NaN",
                 who.text, static_cast<double>(o->min()), static_cast<double>(o->max()));
      return OpParams{ClampParams{o->min(), o->max()}};
    }
    case OpType::kMaxPool2D: {
      const auto* o = op.options_as_Pool2DOptions();
      if (o == nullptr) return wrong_options();
      Pool2DParams p;
      p.pool_h = o->pool_h();
      p.pool_w = o->pool_w();
      p.stride_h = o->stride_h();
      p.stride_w = o->stride_w();
      p.pad_top = o->pad_top();
      p.pad_bottom = o->pad_bottom();
      p.pad_left = o->pad_left();
      p.pad_right = o->pad_right();
      TLV_ENSURE(in_range(p.pool_h, 1, kMaxKernel) && in_range(p.pool_w, 1, kMaxKernel) &&
                     in_range(p.stride_h, 1, kMaxKernel) && in_range(p.stride_w, 1, kMaxKernel),
                 ErrorCode::kModelInvalidOperator,
                 "%s pool %dx%d stride %dx%d: each must be in [1, %d]", who.text, p.pool_h,
                 p.pool_w, p.stride_h, p.stride_w, kMaxKernel);
      TLV_ENSURE(in_range(p.pad_top, 0, p.pool_h - 1) && in_range(p.pad_bottom, 0, p.pool_h - 1) &&
                     in_range(p.pad_left, 0, p.pool_w - 1) &&
                     in_range(p.pad_right, 0, p.pool_w - 1),
                 ErrorCode::kModelInvalidOperator,
                 "%s padding %d,%d,%d,%d must be smaller than the pool window", who.text, p.pad_top,
                 p.pad_bottom, p.pad_left, p.pad_right);
      return OpParams{p};
    }
    case OpType::kPad: {
      const auto* o = op.options_as_PadOptions();
      if (o == nullptr) return wrong_options();
      const Tensor& in = graph.tensor(op.inputs()->Get(0));
      TLV_ENSURE(o->before() && o->after() && o->before()->size() == in.shape.rank &&
                     o->after()->size() == in.shape.rank,
                 ErrorCode::kModelInvalidOperator,
                 "%s needs before/after paddings for each of the input's %zu dimensions", who.text,
                 in.shape.rank);
      TLV_ENSURE(std::isfinite(o->value()), ErrorCode::kModelInvalidOperator,
                 "%s padding value is not finite", who.text);
      PadParams p;
      p.value = o->value();
      for (uint32_t d = 0; d < in.shape.rank; ++d) {
        p.before[d] = o->before()->Get(d);
        p.after[d] = o->after()->Get(d);
        TLV_ENSURE(in_range(p.before[d], 0, 1 << 16) && in_range(p.after[d], 0, 1 << 16),
                   ErrorCode::kModelInvalidOperator, "%s padding of dimension %u is %d/%d",
                   who.text, d, p.before[d], p.after[d]);
      }
      return OpParams{p};
    }
    case OpType::kResizeBilinear: {
      ResizeBilinearParams p;
      if (opt != fb::OpOptions::NONE) {
        const auto* o = op.options_as_ResizeBilinearOptions();
        if (o == nullptr) return wrong_options();
        p.align_corners = o->align_corners();
      }
      return OpParams{p};
    }
    case OpType::kReshape:
      if (opt != fb::OpOptions::NONE && opt != fb::OpOptions::ReshapeOptions)
        return wrong_options();
      return OpParams{NoParams{}};
    default:
      if (opt != fb::OpOptions::NONE && opt != fb::OpOptions::EmptyOptions) return wrong_options();
      return OpParams{NoParams{}};
  }
}

}  // namespace

Status convert_operators(const fb::Graph& fb_graph, Graph& graph) {
  const auto* ops = fb_graph.operators();
  TLV_ENSURE(ops != nullptr && ops->size() > 0, ErrorCode::kModelMalformed,
             "graph has no operators");
  TLV_ENSURE(ops->size() <= kMaxOperators, ErrorCode::kModelMalformed,
             "graph has %u operators, the limit is %zu", ops->size(), kMaxOperators);
  const auto tensor_count = static_cast<int32_t>(graph.tensors.size());
  graph.operators.resize(ops->size());
  for (uint32_t i = 0; i < ops->size(); ++i) {
    const fb::Operator* op = ops->Get(i);
    TLV_ENSURE(op != nullptr, ErrorCode::kModelMalformed, "operator %u is missing", i);
    Operator& out = graph.operators[i];
    const int type = static_cast<int>(op->type());
    TLV_ENSURE(type >= 0 && type <= static_cast<int>(OpType::kDequantize),
               ErrorCode::kModelInvalidOperator, "operator %u has unknown type %d", i, type);
    out.type = static_cast<OpType>(type);
    if (op->name() != nullptr) out.name = {op->name()->c_str(), op->name()->size()};
    const Label who = op_label(graph, i);

    const Arity a = arity(out.type);
    const uint32_t n_in = op->inputs() ? op->inputs()->size() : 0;
    TLV_ENSURE(n_in >= a.min_inputs && n_in <= a.max_inputs, ErrorCode::kModelInvalidOperator,
               "%s has %u inputs, expected %zu..%zu", who.text, n_in, a.min_inputs, a.max_inputs);
    out.input_count = n_in;
    for (uint32_t k = 0; k < n_in; ++k) {
      const int32_t t = op->inputs()->Get(k);
      const bool optional_bias = k == 2 && t == kNoTensor;
      TLV_ENSURE(optional_bias || (t >= 0 && t < tensor_count), ErrorCode::kModelInvalidOperator,
                 "%s input %u refers to tensor %d, the graph has %d tensors", who.text, k, t,
                 tensor_count);
      out.inputs[k] = t;
    }
    TLV_ENSURE(op->outputs() != nullptr && op->outputs()->size() == 1,
               ErrorCode::kModelInvalidOperator, "%s must have exactly one output, has %u",
               who.text, op->outputs() ? op->outputs()->size() : 0u);
    out.output = op->outputs()->Get(0);
    TLV_ENSURE(out.output >= 0 && out.output < tensor_count, ErrorCode::kModelInvalidOperator,
               "%s output refers to tensor %d, the graph has %d tensors", who.text, out.output,
               tensor_count);
    TLV_ASSIGN_OR_RETURN(out.params, convert_params(*op, out.type, graph, who));
  }
  return {};
}

}  // namespace tlvlink::model_internal
