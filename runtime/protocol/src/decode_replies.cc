// Decoding of the flat messages straight into their structs (views into the payload).
#include "protocol_internal.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::protocol {
namespace {
namespace fb = tlvlink::wire;
using internal::verified_root;
using internal::view;
}  // namespace

Result<ErrorReport> decode_error_report(std::span<const std::byte> payload) {
  TLV_ASSIGN_OR_RETURN(const fb::ErrorReport* r,
                       verified_root<fb::ErrorReport>("ErrorReport", payload));
  return ErrorReport{r->code(), view(r->name()), view(r->text()), r->sensor()};
}

Result<Ack> decode_ack(std::span<const std::byte> payload) {
  TLV_ASSIGN_OR_RETURN(const fb::Ack* r, verified_root<fb::Ack>("Ack", payload));
  return Ack{r->command_sequence(), static_cast<CommandKind>(r->kind())};
}

Result<Nack> decode_nack(std::span<const std::byte> payload) {
  TLV_ASSIGN_OR_RETURN(const fb::Nack* r, verified_root<fb::Nack>("Nack", payload));
  return Nack{r->command_sequence(), static_cast<CommandKind>(r->kind()), r->code(),
              view(r->text())};
}

Result<Pong> decode_pong(std::span<const std::byte> payload) {
  TLV_ASSIGN_OR_RETURN(const fb::Pong* r, verified_root<fb::Pong>("Pong", payload));
  return Pong{r->command_sequence(), r->host_send_ns(), r->board_receive_ns()};
}

Result<Command> decode_command(std::span<const std::byte> payload) {
  TLV_ASSIGN_OR_RETURN(const fb::Command* r, verified_root<fb::Command>("Command", payload));
  Command c;
  c.kind = static_cast<CommandKind>(r->kind());
  c.sensor = r->sensor();
  c.grasp_id = r->grasp_id();
  c.event_ns = r->event_ns();
  c.key = view(r->key());
  c.value = view(r->value());
  c.clock_offset_ns = r->clock_offset_ns();
  c.clock_uncertainty_ns = r->clock_uncertainty_ns();
  return c;
}

Status verify_payload(MessageType type, std::span<const std::byte> payload) {
  switch (type) {
    case MessageType::kHello: return decode_hello(payload).status();
    case MessageType::kFramePrediction: return decode_frame_prediction(payload).status();
    case MessageType::kGraspPrediction: return decode_grasp_prediction(payload).status();
    case MessageType::kStats: return decode_stats(payload).status();
    case MessageType::kError: return decode_error_report(payload).status();
    case MessageType::kAck: return decode_ack(payload).status();
    case MessageType::kNack: return decode_nack(payload).status();
    case MessageType::kPong: return decode_pong(payload).status();
    case MessageType::kFrameImage: return decode_frame_image(payload).status();
    case MessageType::kCommand: return decode_command(payload).status();
  }
  return Error::make(ErrorCode::kProtocolUnsupported,
                     "message type 0x%04x is not known to protocol %u.%u",
                     static_cast<unsigned>(type), kVersionMajor, kVersionMinor);
}

}  // namespace tlvlink::protocol
