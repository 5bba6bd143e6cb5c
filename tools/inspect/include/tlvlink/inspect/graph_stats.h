#pragma once
// Per-operator cost figures for `inspect`, `bench` and `quantize-sweep`: MACs, constant (weight)
// bytes, activation bytes, and a liveness-based estimate of peak activation memory.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tlvlink/graph.h"

namespace tlvlink::inspect {

struct OpStats {
  uint64_t macs = 0;            // multiply-accumulates (conv, FC; 0 for other ops)
  size_t weight_bytes = 0;      // constant inputs (weights, bias, constant operands)
  size_t activation_bytes = 0;  // non-constant inputs + output
};

struct GraphStats {
  std::vector<OpStats> ops;  // one per operator, in order
  uint64_t macs = 0;
  size_t parameters = 0;             // elements of all constant tensors
  size_t weight_bytes = 0;           // bytes of all constant tensors
  size_t peak_activation_bytes = 0;  // max over ops of the bytes of activations alive at that op
};

uint64_t op_macs(const Graph& graph, const Operator& op);
GraphStats graph_stats(const Graph& graph);

}  // namespace tlvlink::inspect
