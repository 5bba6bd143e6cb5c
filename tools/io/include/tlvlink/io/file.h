#pragma once
// Whole-file reads and writes for the host tools. Reads open regular files only (a FIFO, a
// directory or /dev/zero is "not a regular file") and check the size against the caller's
// limit before allocating; writes replace the file atomically (tlvlink/atomic_file.h).

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::tools {

// Reads all of `path`; a file larger than max_bytes is an error (kFormat) naming the limit,
// found from fstat before any byte is read.
Result<std::vector<std::byte>> read_file(const std::string& path, size_t max_bytes);
// Replaces `path` with `bytes` atomically; errors carry the path ("disk full", ...).
Status write_file(const std::string& path, std::span<const std::byte> bytes);

}  // namespace tlvlink::tools
