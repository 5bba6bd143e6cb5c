#pragma once
#ifndef TLVLINK_MODEL_PRIVATE
#error \
    "model_internal.h is internal to runtime/model: include the public tlvlink/... headers instead"
#endif
// Internals of model loading: flatbuffer -> validated Graph / Metadata. Each function checks
// one aspect and returns an Error naming the tensor or operator involved.

#include <span>

#include "tlvlink/error.h"
#include "tlvlink/graph.h"
#include "tlvlink/metadata.h"
#include "tlvm_generated.h"

namespace tlvlink::model_internal {

using Buffers = std::span<const std::span<const std::byte>>;

// Printable labels for error messages (fixed buffers: no allocation).
struct Label {
  char text[128];
};
Label tensor_label(const Graph& graph, int32_t index);
Label op_label(const Graph& graph, size_t op_index);
Label shape_label(const Shape& shape);
// Same scales, zero points and axis (pass-through ops keep their input's parameters).
bool same_quantization(const Tensor& a, const Tensor& b);

// The .tlvm file identifier at bytes 4..7 of `raw` (which holds at least 8 bytes); the loader
// and load_file's look at the first bytes both use it.
Status check_identifier(const uint8_t* raw);
// Tensors: shape, dtype, quantization parameters, constant data binding (+ finite floats).
Status convert_tensors(const fb::Graph& fb_graph, Buffers buffers, Graph& graph);
// Operators: type, input/output indices in range, options matching the op type.
Status convert_operators(const fb::Graph& fb_graph, Graph& graph);
// Graph inputs/outputs; topological order; single producer per activation.
Status validate_topology(const fb::Graph& fb_graph, Graph& graph);
// Per-op semantic checks (shapes, dtypes, quantization), split by op family.
Status validate_conv_fc(const Graph& graph, size_t op_index);
Status validate_elementwise(const Graph& graph, size_t op_index);
Status validate_shaping(const Graph& graph, size_t op_index);
// Metadata: input spec against graph input 0, heads against the embedding, golden pairs.
Status convert_metadata(const fb::Metadata* fb_metadata, Buffers buffers, const Graph& graph,
                        Metadata& metadata);

}  // namespace tlvlink::model_internal
