// The operator plan: which Clamps fuse into their producer, which operators the user keeps in
// fp32, and which op types have int8 kernels.

#include <algorithm>
#include <string>

#include "quantizer/quantizer_internal.h"

namespace tlvlink::quantize::quantizer_internal {
namespace {

bool fusable_producer(OpType type) {
  return type == OpType::kConv2D || type == OpType::kFullyConnected || type == OpType::kAdd ||
         type == OpType::kMul;
}

// The activation equal to applying `a` then clamping to [lo, hi], if there is one.
bool combine(Activation a, float lo, float hi, Activation& out) {
  const float l = std::max(activation_min(a), lo), h = std::min(activation_max(a), hi);
  for (Activation candidate : {Activation::kRelu, Activation::kRelu6}) {
    if (l == activation_min(candidate) && h == activation_max(candidate)) {
      out = candidate;
      return true;
    }
  }
  return false;
}

// Conv2D / FullyConnected operator indices in graph order.
std::vector<size_t> linear_ops(const Graph& g) {
  std::vector<size_t> out;
  for (size_t i = 0; i < g.operators.size(); ++i) {
    const OpType t = g.operators[i].type;
    if (t == OpType::kConv2D || t == OpType::kFullyConnected) out.push_back(i);
  }
  return out;
}

Status mark_keep_float(const Graph& g, const std::vector<std::string>& names,
                       std::vector<OpPlan>& plan) {
  const std::vector<size_t> linear = linear_ops(g);
  for (const std::string& name : names) {
    if ((name == "first" || name == "last") && !linear.empty()) {
      plan[name == "first" ? linear.front() : linear.back()].keep_float = true;
      continue;
    }
    bool found = false;
    for (size_t i = 0; i < g.operators.size(); ++i) {
      if (g.operators[i].name == name) {
        plan[i].keep_float = found = true;
      }
    }
    if (!found) {
      std::string known;
      for (const Operator& op : g.operators) {
        if (known.size() > 160) {
          known += ", ...";
          break;
        }
        known += (known.empty() ? "" : ", ") + std::string(op.name);
      }
      return Error::make(ErrorCode::kInvalidArgument,
                         "--keep-float '%s': the model has no operator of that name (first, "
                         "last, %s)",
                         name.c_str(), known.c_str());
    }
  }
  return {};
}

}  // namespace

Activation activation_of(const Operator& op) {
  if (const auto* p = std::get_if<Conv2DParams>(&op.params)) return p->activation;
  if (const auto* p = std::get_if<FullyConnectedParams>(&op.params)) return p->activation;
  if (const auto* p = std::get_if<BinaryParams>(&op.params)) return p->activation;
  return Activation::kNone;
}

bool has_int8_kernel(OpType type) {
  switch (type) {
    case OpType::kConv2D:
    case OpType::kFullyConnected:
    case OpType::kAdd:
    case OpType::kMul:
    case OpType::kClamp:
    case OpType::kSigmoid:
    case OpType::kGlobalAveragePool:
    case OpType::kMaxPool2D:
    case OpType::kPad:
    case OpType::kReshape:
    case OpType::kResizeBilinear: return true;
    case OpType::kQuantize:
    case OpType::kDequantize: return false;
  }
  return false;
}

Result<std::vector<OpPlan>> make_plan(const Graph& g, const QuantizerOptions& options) {
  std::vector<OpPlan> plan(g.operators.size());
  for (size_t i = 0; i < g.operators.size(); ++i) {
    plan[i].activation = activation_of(g.operators[i]);
    plan[i].output = g.operators[i].output;
  }
  TLV_TRY(mark_keep_float(g, options.keep_float, plan));
  if (!options.fuse_clamps) return plan;

  // Consumers per tensor, and the producing operator.
  std::vector<int32_t> consumers(g.tensors.size(), 0), producer(g.tensors.size(), -1);
  for (size_t i = 0; i < g.operators.size(); ++i) {
    const Operator& op = g.operators[i];
    for (size_t k = 0; k < op.input_count; ++k) {
      if (op.inputs[k] != kNoTensor) ++consumers[static_cast<size_t>(op.inputs[k])];
    }
    producer[static_cast<size_t>(op.output)] = static_cast<int32_t>(i);
  }
  for (int32_t out : g.outputs) ++consumers[static_cast<size_t>(out)];  // outputs stay visible

  for (size_t i = 0; i < g.operators.size(); ++i) {
    const Operator& clamp = g.operators[i];
    if (clamp.type != OpType::kClamp || plan[i].keep_float) continue;
    const auto x = static_cast<size_t>(clamp.inputs[0]);
    if (producer[x] < 0 || consumers[x] != 1) continue;
    const auto p = static_cast<size_t>(producer[x]);
    const Operator& prod = g.operators[p];
    if (!fusable_producer(prod.type) || plan[p].keep_float || plan[p].fused_clamp >= 0) continue;
    const ClampParams& c = clamp.get<ClampParams>();
    Activation fused;
    if (!combine(plan[p].activation, c.min, c.max, fused)) continue;
    plan[p].activation = fused;
    plan[p].output = clamp.output;
    plan[p].fused_clamp = static_cast<int32_t>(i);
    plan[i].fused_into = static_cast<int32_t>(p);
  }
  return plan;
}

}  // namespace tlvlink::quantize::quantizer_internal
