#include "tlvlink/model.h"

namespace tlvlink {

// FNV-1a 64 with each buffer's length mixed in, so moving bytes between buffers changes it.
uint64_t content_checksum(std::span<const std::span<const std::byte>> buffers) {
  constexpr uint64_t kOffset = 0xcbf29ce484222325ull;
  constexpr uint64_t kPrime = 0x100000001b3ull;
  uint64_t h = kOffset;
  auto mix = [&](uint8_t b) { h = (h ^ b) * kPrime; };
  for (const auto& buffer : buffers) {
    uint64_t n = buffer.size();
    for (int i = 0; i < 8; ++i) mix(static_cast<uint8_t>(n >> (8 * i)));
    for (std::byte b : buffer) mix(static_cast<uint8_t>(b));
  }
  return h;
}

}  // namespace tlvlink
