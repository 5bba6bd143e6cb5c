#pragma once
// The stream protocol's frame layer (runtime/protocol/README.md is the specification): version,
// message types, flags, the fixed 24-byte header and the size limits. Everything is
// little-endian on the wire.

#include <cstddef>
#include <cstdint>

namespace tlvlink::protocol {

inline constexpr uint8_t kMagic0 = 0x54;  // 'T'
inline constexpr uint8_t kMagic1 = 0x4C;  // 'L'
inline constexpr uint8_t kVersionMajor = 1;
inline constexpr uint8_t kVersionMinor =
    3;  // 1: HeadInfo's cross-validated records; 2: FrameImage;
        // 3: FramePrediction's gate state and score

inline constexpr size_t kHeaderSize = 24;
inline constexpr size_t kCrcSize = 4;
// Largest frame (header + payload + CRC) before COBS encoding. Room for a 2,048-float embedding
// besides the heads; a Hello with 16 heads of 64 labels fits with room to spare.
inline constexpr size_t kMaxFrameSize = 16384;
inline constexpr size_t kMaxPayloadSize = kMaxFrameSize - kHeaderSize - kCrcSize;

// COBS adds one code byte per started run of 254 bytes (plus one); the 0x00 delimiter follows.
constexpr size_t cobs_max_encoded_size(size_t n) { return n + n / 254 + 1; }
inline constexpr size_t kMaxWireFrameSize = cobs_max_encoded_size(kMaxFrameSize) + 1;

enum class MessageType : uint16_t {
  // board -> host
  kHello = 0x01,
  kFramePrediction = 0x02,
  kGraspPrediction = 0x03,
  kStats = 0x04,
  kError = 0x05,
  kAck = 0x06,
  kNack = 0x07,
  kPong = 0x08,
  kFrameImage = 0x09,  // minor 2
  // host -> board
  kCommand = 0x80,
};

// Header flags. Bits 0-7 may be ignored by a reader that does not know them; a reader must
// reject a frame carrying an unknown bit of 8-15 ("must understand", none defined in 1.0).
inline constexpr uint16_t kFlagDelayed = 1u << 0;  // queued while the link was down, sent late
inline constexpr uint16_t kFlagsKnown = kFlagDelayed;
inline constexpr uint16_t kFlagsMustUnderstand = 0xFF00;

struct FrameHeader {
  uint8_t version_major = kVersionMajor;
  uint8_t version_minor = kVersionMinor;
  MessageType type = MessageType::kHello;
  uint16_t flags = 0;
  uint32_t sequence = 0;  // per sender and direction, +1 per frame sent, wraps at 2^32
  uint32_t payload_length = 0;
  int64_t send_ns = 0;  // sender's clock when the frame was written to the link
};

// Header <-> bytes (exactly kHeaderSize). read_header does no validation.
void write_header(const FrameHeader& header, std::byte* out);
FrameHeader read_header(const std::byte* in);

// Hash of the payload schema this build was made with (README "Schema hash"): a Hello carries
// it, a reader compares it with its own.
uint64_t schema_hash();

}  // namespace tlvlink::protocol
