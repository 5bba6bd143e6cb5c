#pragma once
// CRC-32 as zlib, Ethernet and pw_hdlc compute it (reflected polynomial 0xEDB88320, initial
// value and final XOR 0xFFFFFFFF): crc32("123456789") == 0xCBF43926.

#include <cstddef>
#include <cstdint>
#include <span>

namespace tlvlink::protocol {

// `crc` continues an earlier call: crc32(b, crc32(a)) == crc32(a followed by b).
uint32_t crc32(std::span<const std::byte> data, uint32_t crc = 0);

}  // namespace tlvlink::protocol
