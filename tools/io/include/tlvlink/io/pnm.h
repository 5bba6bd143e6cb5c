#pragma once
// Binary Netpbm images: PPM (P6, RGB) and PGM (P5, gray), maxval 255 only. Comments ('#' to end
// of line) are allowed between header fields as the format permits; everything else that is off
// (other magic, maxval != 255, sizes over the limit, short or long pixel data) is an Error
// (kFormat) naming the file.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/io/image.h"

namespace tlvlink::tools {

inline constexpr int32_t kMaxImageSide = 16384;

Result<Image> parse_pnm(std::span<const std::byte> bytes, const std::string& name);
Result<Image> read_pnm(const std::string& path);

// P6 for 3 channels, P5 for 1.
std::vector<std::byte> encode_pnm(const Image& image);
Status write_pnm(const std::string& path, const Image& image);

}  // namespace tlvlink::tools
