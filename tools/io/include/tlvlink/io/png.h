#pragma once
// PNG images through libpng's simplified API (8-bit gray / RGB; palette, 16-bit and alpha are
// converted: alpha dropped, 16-bit reduced to 8).

#include <string>

#include "tlvlink/io/image.h"
#include "tlvlink/error.h"

namespace tlvlink::tools {

// Largest side accepted (as the other image readers).
inline constexpr int32_t kMaxPngSide = 16384;

Result<Image> read_png(const std::string& path);

}  // namespace tlvlink::tools
