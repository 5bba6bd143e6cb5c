#pragma once
// Whole-file reads and writes for the host tools, with a size limit checked before reading.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::tools {

// Reads all of `path`; a file larger than max_bytes is an error (kFormat) naming the limit.
Result<std::vector<std::byte>> read_file(const std::string& path, size_t max_bytes);
// Writes `bytes` to `path` (truncating); errors carry the path and strerror.
Status write_file(const std::string& path, std::span<const std::byte> bytes);

}  // namespace tlvlink::tools
