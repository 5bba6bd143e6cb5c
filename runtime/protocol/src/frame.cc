#include "tlvlink/protocol/frame.h"

#include <array>

#include "tlvlink/protocol/cobs.h"
#include "tlvlink/protocol/crc32.h"

namespace tlvlink::protocol {
namespace {

uint32_t read_u32_le(const std::byte* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
         static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
}

}  // namespace

Result<size_t> encode_frame(FrameHeader header, std::span<const std::byte> payload,
                            std::span<std::byte> out) {
  TLV_ENSURE(payload.size() <= kMaxPayloadSize, ErrorCode::kProtocolTooLarge,
             "frame payload of %zu bytes exceeds the protocol's %zu", payload.size(),
             kMaxPayloadSize);
  header.payload_length = static_cast<uint32_t>(payload.size());
  std::array<std::byte, kHeaderSize> head;
  write_header(header, head.data());
  uint32_t crc = crc32(head);
  crc = crc32(payload, crc);
  const std::array<std::byte, kCrcSize> trailer = {
      std::byte(crc & 0xFF), std::byte((crc >> 8) & 0xFF), std::byte((crc >> 16) & 0xFF),
      std::byte(crc >> 24)};
  TLV_ENSURE(!out.empty(), ErrorCode::kProtocolTooLarge, "no room for a frame");
  CobsEncoder cobs(out.first(out.size() - 1));
  cobs.put(head);
  cobs.put(payload);
  cobs.put(trailer);
  TLV_ASSIGN_OR_RETURN(const size_t n, cobs.finish());
  out[n] = std::byte{0};
  return n + 1;
}

FrameVerdict check_frame(std::span<const std::byte> frame, FrameHeader& header,
                         std::span<const std::byte>& payload) {
  payload = {};
  // The magic, the major version byte and the CRC-32 trailer keep their places in every major
  // version, so a frame is authenticated before its version is judged (README "Versions").
  if (frame.size() < 4 + kCrcSize) return FrameVerdict::kTruncated;
  const size_t body = frame.size() - kCrcSize;
  const bool magic = frame[0] == std::byte{kMagic0} && frame[1] == std::byte{kMagic1};
  const bool readable_header = magic && body >= kHeaderSize;
  if (crc32(frame.first(body)) != read_u32_le(frame.data() + body)) {
    // Shorter than its (unauthenticated) header says: most likely cut short.
    if (readable_header && read_header(frame.data()).payload_length > body - kHeaderSize) {
      return FrameVerdict::kTruncated;
    }
    return FrameVerdict::kCrc;
  }
  if (!magic) return FrameVerdict::kMagic;
  if (static_cast<uint8_t>(frame[2]) != kVersionMajor) {
    header = FrameHeader{};
    header.version_major = static_cast<uint8_t>(frame[2]);
    header.version_minor = static_cast<uint8_t>(frame[3]);
    return FrameVerdict::kVersion;
  }
  if (frame.size() < kHeaderSize + kCrcSize) return FrameVerdict::kTruncated;
  header = read_header(frame.data());
  if (header.payload_length != body - kHeaderSize || header.payload_length > kMaxPayloadSize) {
    return FrameVerdict::kLength;
  }
  if ((header.flags & kFlagsMustUnderstand) != 0) return FrameVerdict::kUnsupportedFlags;
  payload = frame.subspan(kHeaderSize, header.payload_length);
  return FrameVerdict::kOk;
}

const char* frame_verdict_name(FrameVerdict verdict) {
  switch (verdict) {
    case FrameVerdict::kOk: return "ok";
    case FrameVerdict::kOversized: return "oversized";
    case FrameVerdict::kCobs: return "cobs";
    case FrameVerdict::kTruncated: return "truncated";
    case FrameVerdict::kCrc: return "crc";
    case FrameVerdict::kMagic: return "magic";
    case FrameVerdict::kVersion: return "version";
    case FrameVerdict::kLength: return "length";
    case FrameVerdict::kUnsupportedFlags: return "unsupported_flags";
  }
  return "unknown";
}

}  // namespace tlvlink::protocol
