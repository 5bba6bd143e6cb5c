#pragma once
#ifndef TLVLINK_DATASETS_PRIVATE
#error "provenance.h is internal to tools/datasets: include its public headers instead"
#endif
// tlvlink_sim.json: what made a dataset and how it was written. Internal.

#include <string>

#include "meta.h"
#include "tlvlink/datasets/detect.h"
#include "tlvlink/datasets/writer.h"

namespace tlvlink::datasets {

inline constexpr const char* kProvenanceFile = kGeneratorRecord;

// Writes DIR/tlvlink_sim.json: {"format", "generator", "writer", "counts"}; `writer_extra`
// holds format-specific writer options. Adds the file to `summary`.
Status write_provenance(const std::string& dir, const char* format, const WriterOptions& options,
                        const OrderedJson& writer_extra, WriteSummary& summary);

}  // namespace tlvlink::datasets
