#include "tlvlink/protocol/wire.h"

#include <cstring>

namespace tlvlink::protocol {
namespace {

template <typename T>
void put_le(std::byte* out, T value) {
  for (size_t i = 0; i < sizeof(T); ++i)
    out[i] = static_cast<std::byte>((static_cast<uint64_t>(value) >> (8 * i)) & 0xFF);
}

template <typename T>
T get_le(const std::byte* in) {
  uint64_t v = 0;
  for (size_t i = 0; i < sizeof(T); ++i) v |= static_cast<uint64_t>(in[i]) << (8 * i);
  return static_cast<T>(v);
}

}  // namespace

// Layout (README "Header"): magic[2] major minor type:u16 flags:u16 sequence:u32
// payload_length:u32 send_ns:i64.
void write_header(const FrameHeader& h, std::byte* out) {
  out[0] = std::byte{kMagic0};
  out[1] = std::byte{kMagic1};
  out[2] = std::byte{h.version_major};
  out[3] = std::byte{h.version_minor};
  put_le(out + 4, static_cast<uint16_t>(h.type));
  put_le(out + 6, h.flags);
  put_le(out + 8, h.sequence);
  put_le(out + 12, h.payload_length);
  put_le(out + 16, static_cast<uint64_t>(h.send_ns));
}

FrameHeader read_header(const std::byte* in) {
  FrameHeader h;
  h.version_major = static_cast<uint8_t>(in[2]);
  h.version_minor = static_cast<uint8_t>(in[3]);
  h.type = static_cast<MessageType>(get_le<uint16_t>(in + 4));
  h.flags = get_le<uint16_t>(in + 6);
  h.sequence = get_le<uint32_t>(in + 8);
  h.payload_length = get_le<uint32_t>(in + 12);
  h.send_ns = static_cast<int64_t>(get_le<uint64_t>(in + 16));
  return h;
}

// TLVLINK_STREAM_SCHEMA_HASH is computed by runtime/protocol/CMakeLists.txt from stream.fbs.
uint64_t schema_hash() { return TLVLINK_STREAM_SCHEMA_HASH; }

}  // namespace tlvlink::protocol
