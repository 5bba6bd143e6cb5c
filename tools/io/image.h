#pragma once
// An 8-bit image in memory: rows top to bottom, pixels interleaved (RGB or gray).

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tlvlink::tools {

struct Image {
  int32_t width = 0, height = 0, channels = 0;  // channels: 1 (gray) or 3 (RGB)
  std::vector<uint8_t> pixels;                  // height * width * channels

  uint8_t at(int32_t y, int32_t x, int32_t c) const {
    return pixels[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) *
                      static_cast<size_t>(channels) +
                  static_cast<size_t>(c)];
  }
};

}  // namespace tlvlink::tools
