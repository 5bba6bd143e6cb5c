#pragma once
// `record --stream`: a stream recording's (.tlvrec or .mcap) frame images of one sensor as a
// camera recording. Defined in listen.cc (tools/foxglove reads both kinds); listen_unavailable.cc
// says why not in a build without the stream's host side.

#include <cstdint>
#include <string>

#include "tlvlink/error.h"
#include "tlvlink/record/record.h"

namespace tlvlink::cli {

Result<record::RecordReport> record_stream_images(const std::string& stream, int32_t sensor,
                                                  const record::RecordOptions& options,
                                                  const std::string& out_path);

}  // namespace tlvlink::cli
