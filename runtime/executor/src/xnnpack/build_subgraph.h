#pragma once
#ifndef TLVLINK_EXECUTOR_PRIVATE
#error \
    "build_subgraph.h is internal to runtime/executor: include the public tlvlink/... headers instead"
#endif
// Builds an XNNPACK subgraph from (part of) a model graph, and explains a runtime-creation
// failure by the operator that causes it.

#include <cstdint>
#include <span>

#include "tlvlink/error.h"
#include "tlvlink/graph.h"
#include "xnnpack/define_tensors.h"
#include "xnnpack/owned_memory.h"
#include "xnnpack/xnn_api.h"

namespace tlvlink::xnn {

// Defines every tensor flagged external (so the runtime can be set up with all of them, even
// one no operator reads), then the operators `ops` in order. Memory XNNPACK must keep (scales,
// transposed weights, padded constants) goes into `memory`, which must outlive any runtime
// created from the subgraph.
Result<Subgraph> build_subgraph(const Graph& graph, std::span<const ExternalFlags> flags,
                                std::span<const int32_t> ops, OwnedMemory& memory);

// xnn_create_runtime_v2 reports only a status, without saying which node it refused (most
// parameter checks happen when operators are created, not when they are defined). This creates
// each operator on its own and returns the error of the first one XNNPACK refuses, naming it;
// `whole` if every operator is accepted alone. Runs only on the error path.
Error diagnose_runtime_failure(const Graph& graph, const Error& whole);

}  // namespace tlvlink::xnn
