#include "xnnpack/build_subgraph.h"

#include <vector>

#include "xnnpack/define_ops.h"

namespace tlvlink::xnn {

Result<Subgraph> build_subgraph(const Graph& graph, std::span<const ExternalFlags> flags,
                                std::span<const int32_t> ops, OwnedMemory& memory) {
  TLV_ASSIGN_OR_RETURN(Subgraph subgraph,
                       Subgraph::create(static_cast<uint32_t>(graph.tensors.size())));
  ValueTable values(graph, subgraph, memory, flags);
  for (size_t t = 0; t < flags.size(); ++t) {
    if ((flags[t].input || flags[t].output) && !graph.tensors[t].is_constant()) {
      TLV_TRY(values.value(static_cast<int32_t>(t)));
    }
  }
  for (int32_t op : ops) TLV_TRY(define_operator(values, op));
  return subgraph;
}

Error diagnose_runtime_failure(const Graph& graph, const Error& whole) {
  for (size_t i = 0; i < graph.operators.size(); ++i) {
    const Operator& op = graph.operators[i];
    const int32_t index = static_cast<int32_t>(i);
    // The operator alone: its activation inputs become external inputs, its output external.
    std::vector<ExternalFlags> flags(graph.tensors.size());
    for (size_t k = 0; k < op.input_count; ++k) {
      if (op.inputs[k] != kNoTensor) flags[static_cast<size_t>(op.inputs[k])].input = true;
    }
    flags[static_cast<size_t>(op.output)].output = true;
    OwnedMemory memory;
    const int32_t only[] = {index};
    Result<Subgraph> subgraph = build_subgraph(graph, flags, only, memory);
    if (!subgraph.ok()) return subgraph.error();
    TLV_ASSIGN_OR_RETURN(ThreadPool no_pool, ThreadPool::create(1));
    Result<Runtime> runtime = Runtime::create(*subgraph, no_pool, operator_ref(graph, index));
    if (!runtime.ok()) return runtime.error();
  }
  return whole;
}

}  // namespace tlvlink::xnn
