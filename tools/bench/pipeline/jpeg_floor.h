#pragma once
// What decoding a JPEG costs at its floor and with the shortcuts libjpeg-turbo offers, through its
// libjpeg API (the TurboJPEG API has no entropy-only or cropped decode): the entropy (Huffman)
// decoding every decode pays, and a DCT-scaled decode of only the rows and columns a view needs
// (jpeg_crop_scanline / jpeg_skip_scanlines). Benchmark-only code (host).

#include <cstdint>
#include <span>
#include <vector>

namespace tlvlink::bench {

// Huffman-decodes every coefficient, skipping IDCT, upsampling and colour conversion.
bool entropy_decode(std::span<const uint8_t> jpeg);

// Decodes at 1/scale only the region [x0, x0+w) x [y0, y0+h) of the scaled image (w, h, x0, y0
// in scaled pixels; the decoder widens x to iMCU boundaries) into `rgb`. Returns false on error.
bool cropped_decode(std::span<const uint8_t> jpeg, int32_t scale, int32_t x0, int32_t y0, int32_t w,
                    int32_t h, std::vector<uint8_t>& rgb);

// The restart interval in MCUs (0: no restart markers; slices cannot be decoded in parallel).
int32_t restart_interval(std::span<const uint8_t> jpeg);

}  // namespace tlvlink::bench
