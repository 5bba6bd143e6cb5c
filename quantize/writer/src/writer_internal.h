#pragma once
#ifndef TLVLINK_MODEL_WRITER_PRIVATE
#error "writer_internal.h is internal to quantize/writer: include its public headers instead"
#endif
// Serialisation helpers shared by the ModelBuilder's files.

#include "tlvlink/quantize/model_builder.h"
#include "tlvlink/verify/golden_heads.h"
#include "tlvm_generated.h"

namespace tlvlink::quantize::writer_internal {

// Op options union for an operator (type + offset).
std::pair<fb::OpOptions, flatbuffers::Offset<void>> write_options(
    flatbuffers::FlatBufferBuilder& fbb, OpType type, const OpParams& params, size_t input_rank);

struct GoldenIndices {
  uint32_t input, output;  // buffer indices
};

// Metadata table. Golden pairs refer to buffers the caller has already placed; `heads` (may be
// null) are their head outputs.
flatbuffers::Offset<fb::Metadata> write_metadata(flatbuffers::FlatBufferBuilder& fbb,
                                                 const MetadataSpec& spec,
                                                 std::span<const GoldenIndices> golden_buffers,
                                                 const verify::GoldenHeadOutputs* heads,
                                                 uint64_t checksum);

}  // namespace tlvlink::quantize::writer_internal
