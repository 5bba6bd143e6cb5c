#pragma once
// 8-bit images: a borrowed view (what the frame path passes around) and an owned image (what
// host tools and datasets keep). Rows top to bottom, pixels interleaved: RGB (3 channels) or
// gray (1).

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tlvlink::image {

// Borrowed pixels, valid while their owner is. stride 0 means tightly packed rows.
struct ImageView {
  const uint8_t* pixels = nullptr;
  int32_t width = 0, height = 0, channels = 0;
  size_t stride = 0;

  size_t row_bytes() const {
    return stride != 0 ? stride : static_cast<size_t>(width) * static_cast<size_t>(channels);
  }
  const uint8_t* row(int32_t y) const { return pixels + static_cast<size_t>(y) * row_bytes(); }
  uint8_t at(int32_t y, int32_t x, int32_t c) const {
    return row(y)[static_cast<size_t>(x) * static_cast<size_t>(channels) + static_cast<size_t>(c)];
  }
};

// Owned, tightly packed pixels: height * width * channels bytes.
struct Image {
  int32_t width = 0, height = 0, channels = 0;  // channels: 1 (gray) or 3 (RGB)
  std::vector<uint8_t> pixels;

  uint8_t at(int32_t y, int32_t x, int32_t c) const {
    return pixels[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) *
                      static_cast<size_t>(channels) +
                  static_cast<size_t>(c)];
  }
  ImageView view() const { return {pixels.data(), width, height, channels, 0}; }
};

}  // namespace tlvlink::image
