#pragma once
#ifndef TLVLINK_EXECUTOR_PRIVATE
#error \
    "define_tensors.h is internal to runtime/executor: include the public tlvlink/... headers instead"
#endif
// Maps the model's tensors to XNNPACK values. Activations are defined on first use with the
// model's dims and per-tensor quantization (fp32 or qint8); graph inputs/outputs (and, with
// expose_all_tensors, every activation) are external values whose id is the tensor index.
// Weights and biases are not defined here: define_conv.cc builds them in the layout each
// XNNPACK node wants, with the helpers below.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/graph.h"
#include "xnnpack/owned_memory.h"
#include "xnnpack/xnn_api.h"

namespace tlvlink::xnn {

struct ExternalFlags {
  bool input = false;
  bool output = false;
};

// Dims of a shape in XNNPACK's size_t form; `rank` entries are meaningful.
struct Dims {
  std::array<size_t, Shape::kMaxRank> d{};
  size_t rank = 0;
  std::span<const size_t> span() const { return {d.data(), rank}; }
};
Dims dims_of(const Shape& shape);

NodeRef tensor_ref(const Graph& graph, int32_t tensor);
NodeRef operator_ref(const Graph& graph, int32_t op);

class ValueTable {
 public:
  // flags: one entry per tensor. Borrows everything for the table's lifetime.
  ValueTable(const Graph& graph, Subgraph& subgraph, OwnedMemory& memory,
             std::span<const ExternalFlags> flags);

  // The XNNPACK value of an activation (or of a constant used as a plain operand, copied into
  // padded memory), defined on first use.
  Result<uint32_t> value(int32_t tensor);

  // An internal value with `like`'s dtype and quantization but other dims (e.g. the [N,1,1,C]
  // view of a fully-connected input).
  Result<uint32_t> define_internal(const Tensor& like, std::span<const size_t> dims,
                                   const NodeRef& who);

  // A static value (weights / bias) from a prepared description.
  Result<uint32_t> define_static(const ValueDesc& desc, const NodeRef& who) {
    return subgraph_.define_value(desc, who);
  }

  const Graph& graph() const { return graph_; }
  Subgraph& subgraph() { return subgraph_; }
  OwnedMemory& memory() { return memory_; }

 private:
  Result<ValueDesc> activation_desc(int32_t tensor, const Dims& dims);

  const Graph& graph_;
  Subgraph& subgraph_;
  OwnedMemory& memory_;
  std::span<const ExternalFlags> flags_;
  std::vector<uint32_t> ids_;  // per tensor; kInvalidValueId until defined
};

}  // namespace tlvlink::xnn
