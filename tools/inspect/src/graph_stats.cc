#include "tlvlink/inspect/graph_stats.h"

#include <algorithm>

namespace tlvlink::inspect {

uint64_t op_macs(const Graph& g, const Operator& op) {
  switch (op.type) {
    case OpType::kConv2D: {
      const Shape& out = g.tensor(op.output).shape;
      const Shape& w = g.tensor(op.inputs[1]).shape;  // [Cout, KH, KW, Cin/groups]
      return static_cast<uint64_t>(out.elements()) * static_cast<uint64_t>(w[1]) * w[2] * w[3];
    }
    case OpType::kFullyConnected: {
      const Shape& out = g.tensor(op.output).shape;   // [N, Cout]
      const Shape& w = g.tensor(op.inputs[1]).shape;  // [Cout, Cin]
      return static_cast<uint64_t>(out.elements()) * static_cast<uint64_t>(w[1]);
    }
    default: return 0;
  }
}

GraphStats graph_stats(const Graph& g) {
  GraphStats s;
  for (const Tensor& t : g.tensors) {
    if (!t.is_constant()) continue;
    s.parameters += t.shape.elements();
    s.weight_bytes += t.bytes();
  }
  // Liveness: an activation lives from its producer (or the start, for graph inputs) to its
  // last consumer (or the end, for graph outputs). Without in-place reuse this is the peak an
  // arena planner has to provide.
  const size_t n = g.operators.size();
  std::vector<size_t> first(g.tensors.size(), n), last(g.tensors.size(), 0);
  for (int32_t t : g.inputs) first[static_cast<size_t>(t)] = 0;
  for (size_t i = 0; i < n; ++i) {
    const Operator& op = g.operators[i];
    for (size_t k = 0; k < op.input_count; ++k) {
      if (op.inputs[k] == kNoTensor) continue;
      last[static_cast<size_t>(op.inputs[k])] =
          std::max(last[static_cast<size_t>(op.inputs[k])], i);
    }
    first[static_cast<size_t>(op.output)] = std::min(first[static_cast<size_t>(op.output)], i);
    last[static_cast<size_t>(op.output)] = std::max(last[static_cast<size_t>(op.output)], i);
  }
  for (int32_t t : g.outputs) last[static_cast<size_t>(t)] = n == 0 ? 0 : n - 1;
  for (size_t i = 0; i < n; ++i) {
    const Operator& op = g.operators[i];
    OpStats o;
    o.macs = op_macs(g, op);
    for (size_t k = 0; k < op.input_count; ++k) {
      if (op.inputs[k] == kNoTensor) continue;
      const Tensor& t = g.tensor(op.inputs[k]);
      (t.is_constant() ? o.weight_bytes : o.activation_bytes) += t.bytes();
    }
    o.activation_bytes += g.tensor(op.output).bytes();
    size_t live = 0;
    for (size_t t = 0; t < g.tensors.size(); ++t) {
      if (!g.tensors[t].is_constant() && first[t] <= i && i <= last[t] && first[t] < n)
        live += g.tensors[t].bytes();
    }
    s.peak_activation_bytes = std::max(s.peak_activation_bytes, live);
    s.macs += o.macs;
    s.ops.push_back(o);
  }
  return s;
}

}  // namespace tlvlink::inspect
