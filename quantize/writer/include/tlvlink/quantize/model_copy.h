#pragma once
// "Same graph, new metadata": a ModelBuilder holding everything of a loaded model — tensors
// (names, dtypes, shapes, quantization, constant bytes), operators with their parameters, graph
// inputs/outputs, golden pairs — with the metadata replaced. Tensor and operator indices are
// kept, so the written model loads and runs bit-identically to the original.
//
//   MetadataSpec meta = metadata_spec_from(model.metadata());
//   meta.linear_heads = fitted;
//   auto builder = rebuild_with_metadata(model, meta);
//   std::vector<std::byte> file = builder->finish();

#include "tlvlink/error.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/model_builder.h"

namespace tlvlink::quantize {

// An owned copy of loaded metadata (golden pairs are not copied).
MetadataSpec metadata_spec_from(const Metadata& metadata);

// `metadata.golden` is used as given when non-empty; when empty, the model's golden pairs are
// copied. Errors: a constant whose data size disagrees with its shape (cannot happen for a
// model that passed Model::load, checked anyway).
Result<ModelBuilder> rebuild_with_metadata(const Model& model, const MetadataSpec& metadata);

// The file of that copy, loaded once before anyone gets it. Errors: rebuild_with_metadata's,
// and the copy failing to load (the loader's error, "the copy with the new metadata does not
// load").
Result<std::vector<std::byte>> model_with_metadata(const Model& model,
                                                   const MetadataSpec& metadata);

}  // namespace tlvlink::quantize
