#pragma once
// One frame on the wire: COBS(header || payload || CRC-32) followed by a 0x00 delimiter.
// encode_frame builds it; check_frame validates a COBS-decoded frame. No allocation, no I/O.

#include <cstddef>
#include <cstdint>
#include <span>

#include "tlvlink/error.h"
#include "tlvlink/protocol/wire.h"

namespace tlvlink::protocol {

// Writes one frame into `out` (at least cobs_max_encoded_size(kHeaderSize + payload + kCrcSize)
// + 1 bytes; kMaxWireFrameSize always suffices). header.payload_length is taken from
// payload.size(). Returns the bytes written, delimiter included.
Result<size_t> encode_frame(FrameHeader header, std::span<const std::byte> payload,
                            std::span<std::byte> out);

// What a receiver concluded about one delimited segment. Checked in this order.
enum class FrameVerdict : uint8_t {
  kOk = 0,
  kOversized,         // segment longer than kMaxWireFrameSize: not decoded
  kCobs,              // a COBS code byte runs past the end of the segment
  kTruncated,         // shorter than a header + CRC, or shorter than its header says (CRC fails)
  kCrc,               // CRC-32 mismatch: corrupted
  kMagic,             // CRC fine but not "TL": not a tlvlink frame
  kVersion,           // CRC fine, another major version: refused
  kLength,            // header payload_length disagrees with the frame's size
  kUnsupportedFlags,  // a "must understand" flag this reader does not know
};
const char* frame_verdict_name(FrameVerdict verdict);  // "ok", "crc", ...

// Validates one COBS-decoded frame. Sets `header` whenever it could be read (kOk, kVersion,
// kLength, kUnsupportedFlags) and `payload` (a view into `frame`) on kOk.
FrameVerdict check_frame(std::span<const std::byte> frame, FrameHeader& header,
                         std::span<const std::byte>& payload);

}  // namespace tlvlink::protocol
