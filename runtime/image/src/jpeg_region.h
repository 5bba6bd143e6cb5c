#pragma once
#ifndef TLVLINK_IMAGE_PRIVATE
#error "jpeg_region.h is internal to runtime/image"
#endif
// A DCT-scaled decode of only a region of a JPEG, through libjpeg-turbo's libjpeg API (the
// TurboJPEG API cannot crop): rows above the region are skipped (entropy-decoded only), columns
// outside it are neither transformed nor colour-converted. For a GelSight Mini frame at 1/8
// this costs the entropy-decoding floor instead of ~16 % more (tools/bench/pipeline).
// A truncated or corrupt stream is an error (warnings are errors, as with TJFLAG_STOPONWARNING).

#include <cstdint>
#include <span>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::image::internal {

struct Region {
  int32_t x = 0, y = 0, width = 0, height = 0;  // in scaled pixels
};

class JpegRegionDecoder {
 public:
  // For frames of width x height decoded at 1/scale, the scaled region `want`. Allocates the
  // output rows once.
  Status init(int32_t width, int32_t height, int32_t scale, Region want);
  // Decodes into pixels(): rows want.y .. want.y + want.height, columns got().x .. got().x +
  // got().width (the start widened to the decoder's iMCU boundary), RGB, got().width * 3 per row.
  Status decode(std::span<const uint8_t> jpeg, const char* what);
  const Region& got() const { return got_; }
  const uint8_t* pixels() const { return pixels_.data(); }
  size_t row_bytes() const { return static_cast<size_t>(want_.width + 16 / scale_ + 1) * 3; }

 private:
  int32_t width_ = 0, height_ = 0, scale_ = 1;
  Region want_, got_;
  std::vector<uint8_t> pixels_;
};

}  // namespace tlvlink::image::internal
