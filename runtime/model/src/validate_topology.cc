// Graph structure: inputs/outputs, topological order, one producer per activation.

#include <vector>

#include "model_internal.h"

namespace tlvlink::model_internal {
namespace {

Status read_index_list(const flatbuffers::Vector<int32_t>* list, const char* what,
                       const Graph& graph, std::vector<int32_t>& out) {
  TLV_ENSURE(list != nullptr && list->size() > 0, ErrorCode::kModelMalformed, "graph has no %s",
             what);
  TLV_ENSURE(list->size() <= 64, ErrorCode::kModelMalformed, "graph has %u %s, the limit is 64",
             list->size(), what);
  for (uint32_t i = 0; i < list->size(); ++i) {
    const int32_t t = list->Get(i);
    TLV_ENSURE(t >= 0 && static_cast<size_t>(t) < graph.tensors.size(), ErrorCode::kModelMalformed,
               "graph %s %u refers to tensor %d, the graph has %zu", what, i, t,
               graph.tensors.size());
    TLV_ENSURE(!graph.tensor(t).is_constant(), ErrorCode::kModelMalformed,
               "graph %s %u is %s, which is a constant", what, i, tensor_label(graph, t).text);
    for (int32_t seen : out) {
      TLV_ENSURE(seen != t, ErrorCode::kModelMalformed, "graph %s lists %s twice", what,
                 tensor_label(graph, t).text);
    }
    out.push_back(t);
  }
  return {};
}

}  // namespace

Status validate_topology(const fb::Graph& fb_graph, Graph& graph) {
  TLV_TRY(read_index_list(fb_graph.inputs(), "inputs", graph, graph.inputs));
  TLV_TRY(read_index_list(fb_graph.outputs(), "outputs", graph, graph.outputs));

  std::vector<int32_t> producer(graph.tensors.size(), -2);  // -2: none, -1: graph input
  for (int32_t t : graph.inputs) producer[static_cast<size_t>(t)] = -1;

  for (size_t i = 0; i < graph.operators.size(); ++i) {
    const Operator& op = graph.operators[i];
    for (size_t k = 0; k < op.input_count; ++k) {
      const int32_t t = op.inputs[k];
      if (t == kNoTensor) continue;
      TLV_ENSURE(graph.tensor(t).is_constant() || producer[static_cast<size_t>(t)] != -2,
                 ErrorCode::kModelInvalidOperator,
                 "%s reads %s before any operator writes it (operators must be in "
                 "topological order)",
                 op_label(graph, i).text, tensor_label(graph, t).text);
    }
    const int32_t out = op.output;
    TLV_ENSURE(!graph.tensor(out).is_constant(), ErrorCode::kModelInvalidOperator,
               "%s writes %s, which is a constant", op_label(graph, i).text,
               tensor_label(graph, out).text);
    const int32_t prev = producer[static_cast<size_t>(out)];
    TLV_ENSURE(prev == -2, ErrorCode::kModelInvalidOperator, "%s writes %s, which is already %s",
               op_label(graph, i).text, tensor_label(graph, out).text,
               prev == -1 ? "a graph input" : "written by an earlier operator");
    producer[static_cast<size_t>(out)] = static_cast<int32_t>(i);
  }
  for (int32_t t : graph.outputs) {
    TLV_ENSURE(producer[static_cast<size_t>(t)] >= 0, ErrorCode::kModelMalformed,
               "graph output %s is not written by any operator", tensor_label(graph, t).text);
  }
  return {};
}

}  // namespace tlvlink::model_internal
