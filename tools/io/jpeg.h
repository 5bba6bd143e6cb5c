#pragma once
// JPEG encode/decode through libturbojpeg (Debian's libturbojpeg0-dev), including decoding at
// a reduced scale (1/2, 1/4, 1/8: the DCT does the downscale, so an 8 MP MJPEG frame costs a
// fraction of a full decode). Errors name the file/stream and libturbojpeg's reason.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/image.h"
#include "tlvlink/error.h"

namespace tlvlink::tools {

// Largest JPEG side accepted by decode (a GelSight Mini frame is 3280x2464).
inline constexpr int32_t kMaxJpegSide = 16384;

// RGB (channels 3) or gray (channels 1) image -> baseline JPEG, quality in [1, 100], 4:2:0 for
// RGB.
Result<std::vector<uint8_t>> encode_jpeg(const Image& image, int32_t quality);

// JPEG bytes -> RGB image, optionally downscaled by 1/scale_denominator (1, 2, 4 or 8).
// `name` (file path or "stream") is used in error messages.
Result<Image> decode_jpeg(std::span<const uint8_t> bytes, const std::string& name,
                          int32_t scale_denominator = 1);

Result<Image> read_jpeg(const std::string& path, int32_t scale_denominator = 1);
Status write_jpeg(const std::string& path, const Image& image, int32_t quality);

}  // namespace tlvlink::tools
