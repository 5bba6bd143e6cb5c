#pragma once
// The memory an image decode may take, checked from the header before any pixel buffer is
// allocated: a few bytes declaring 16384x16384 must not cost 800 MB. Two rules, both errors
// (kFormat, naming the image, the declared size and the limit), never a truncation:
// - at most kMaxImagePixels pixels (16 Mi, 4096x4096: twice a GelSight Mini frame of
//   3280x2464; the RGB buffer is then at most 48 MiB, plus at most 2 bytes per pixel and
//   component of libjpeg's coefficient buffers for a progressive JPEG: the decoders' share of
//   every command's memory budget, tools/cli/README.md);
// - at most `max_ratio` decoded bytes per byte of file: a stream cannot plausibly expand more
//   than its format's densest coding allows (ratios below, with the reason for each number).

#include <cstddef>
#include <cstdint>

#include "tlvlink/error.h"

namespace tlvlink::image {

inline constexpr int64_t kMaxImagePixels = int64_t{16} << 20;

// JPEG: Huffman coding spends at least 1 bit per 8x8 block (a progressive DC scan with 1-bit
// codes; baseline needs 2), so one file byte holds at most 8 blocks = 512 pixels = 1536 RGB
// bytes; 2048 leaves headroom. Only arithmetic coding could go further, and no camera or
// dataset writes it.
inline constexpr int64_t kJpegMaxRatio = 2048;
// PNG: deflate expands at most 1032:1; at 1 bit per pixel (palette or gray) one inflated byte
// is 8 pixels = 24 RGB bytes, so 1032 x 24. Loose by nature: for PNG the pixel cap does the work.
inline constexpr int64_t kPngMaxRatio = 1032 * 24;

// OK when width x height x channels fits both rules for a `file_bytes`-byte stream.
// `format` ("JPEG", "PNG") and `what` (the path or frame name) go into the message.
Status check_decode_budget(int64_t width, int64_t height, int64_t channels, size_t file_bytes,
                           int64_t max_ratio, const char* format, const char* what);

}  // namespace tlvlink::image
