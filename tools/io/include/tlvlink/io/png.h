#pragma once
// PNG images through libpng's simplified API (8-bit gray / RGB; palette, 16-bit and alpha are
// converted: alpha dropped, 16-bit reduced to 8).

#include <cstddef>
#include <span>
#include <string>

#include "tlvlink/error.h"
#include "tlvlink/io/image.h"

namespace tlvlink::tools {

// Largest side accepted (as the other image readers).
inline constexpr int32_t kMaxPngSide = 16384;
// Largest PNG file read_png reads: the pixel cap's RGB size (image/decode_budget.h); a larger
// compressed file is not a plausible PNG the decoder would accept.
inline constexpr size_t kMaxPngFileBytes = size_t{48} << 20;

// PNG bytes in memory; `name` (the path, or "stream") prefixes errors (kFormat).
Result<Image> decode_png(std::span<const std::byte> bytes, const std::string& name);
Result<Image> read_png(const std::string& path);

}  // namespace tlvlink::tools
