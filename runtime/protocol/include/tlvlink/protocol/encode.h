#pragma once
// Message -> flatbuffers payload -> frame, with no allocation: the payload is built inside the
// caller's buffer (a flatbuffers builder whose allocator hands out that buffer and never grows).
// A message that could exceed the buffer is refused before anything is built.

#include <cstddef>
#include <span>

#include "tlvlink/error.h"
#include "tlvlink/protocol/frame.h"
#include "tlvlink/protocol/messages.h"

namespace tlvlink::protocol {

// FrameImage: a payload of a message with `data_bytes` image bytes and `mask_bytes` mask bytes
// is at most this large (the encoder's exact layout; tests check it): a board sizes its JPEG
// buffer as kMaxPayloadSize - frame_image_overhead(mask_bytes).
constexpr size_t frame_image_overhead(size_t mask_bytes) { return 160 + mask_bytes; }

// A buffer that holds the build of any message whose payload fits kMaxPayloadSize.
inline constexpr size_t kEncodeBufferSize = 2 * kMaxFrameSize;
// Arrays (sensors, heads, labels per head, stage names, drops, sensor stats) hold at most this
// many entries; more is kInvalidArgument.
inline constexpr size_t kMaxListLength = 256;

// Each returns the payload: a subspan at the end of `buffer` (which must be 8-byte aligned).
// kProtocolTooLarge when the message may not fit `buffer` or is larger than kMaxPayloadSize.
Result<std::span<const std::byte>> encode_payload(const Hello& m, std::span<std::byte> buffer);
Result<std::span<const std::byte>> encode_payload(const FramePrediction& m,
                                                  std::span<std::byte> buffer);
Result<std::span<const std::byte>> encode_payload(const GraspPrediction& m,
                                                  std::span<std::byte> buffer);
Result<std::span<const std::byte>> encode_payload(const Stats& m, std::span<std::byte> buffer);
Result<std::span<const std::byte>> encode_payload(const ErrorReport& m,
                                                  std::span<std::byte> buffer);
Result<std::span<const std::byte>> encode_payload(const Ack& m, std::span<std::byte> buffer);
Result<std::span<const std::byte>> encode_payload(const Nack& m, std::span<std::byte> buffer);
Result<std::span<const std::byte>> encode_payload(const Pong& m, std::span<std::byte> buffer);
Result<std::span<const std::byte>> encode_payload(const FrameImage& m, std::span<std::byte> buffer);
Result<std::span<const std::byte>> encode_payload(const Command& m, std::span<std::byte> buffer);

// Payload and frame in one call: header.type is set from the message; `scratch` holds the
// payload build (kEncodeBufferSize suffices), `out` the frame (kMaxWireFrameSize suffices).
// Returns the wire bytes written to `out`, delimiter included.
template <typename M>
Result<size_t> encode_message(const M& message, FrameHeader header, std::span<std::byte> scratch,
                              std::span<std::byte> out) {
  TLV_ASSIGN_OR_RETURN(const std::span<const std::byte> payload, encode_payload(message, scratch));
  header.type = MessageTypeOf<M>::value;
  return encode_frame(header, payload, out);
}

}  // namespace tlvlink::protocol
