#include "tlvlink/listen/message.h"

#include <cstring>

#include "tlvlink/protocol/names.h"

namespace tlvlink::listen {

Message::Message(const protocol::FrameHeader& header, std::span<const std::byte> payload,
                 int64_t receive_ns)
    : header_(header),
      receive_ns_(receive_ns),
      storage_((payload.size() + 7) / 8),
      size_(payload.size()) {
  if (size_ > 0) std::memcpy(storage_.data(), payload.data(), size_);
}

Status Message::expect(protocol::MessageType type) const {
  if (header_.type == type) return Status();
  const char* have = protocol::message_type_name(header_.type);
  return Error::make(ErrorCode::kInvalidState, "message %u is a %s, not a %s", header_.sequence,
                     have ? have : "message of an unknown type", protocol::message_type_name(type));
}

Result<protocol::HelloView> Message::hello() const {
  TLV_TRY(expect(protocol::MessageType::kHello));
  return protocol::decode_hello(payload());
}
Result<protocol::FramePredictionView> Message::frame_prediction() const {
  TLV_TRY(expect(protocol::MessageType::kFramePrediction));
  return protocol::decode_frame_prediction(payload());
}
Result<protocol::GraspPredictionView> Message::grasp_prediction() const {
  TLV_TRY(expect(protocol::MessageType::kGraspPrediction));
  return protocol::decode_grasp_prediction(payload());
}
Result<protocol::StatsView> Message::stats() const {
  TLV_TRY(expect(protocol::MessageType::kStats));
  return protocol::decode_stats(payload());
}
Result<protocol::ErrorReport> Message::error_report() const {
  TLV_TRY(expect(protocol::MessageType::kError));
  return protocol::decode_error_report(payload());
}
Result<protocol::Ack> Message::ack() const {
  TLV_TRY(expect(protocol::MessageType::kAck));
  return protocol::decode_ack(payload());
}
Result<protocol::Nack> Message::nack() const {
  TLV_TRY(expect(protocol::MessageType::kNack));
  return protocol::decode_nack(payload());
}
Result<protocol::Pong> Message::pong() const {
  TLV_TRY(expect(protocol::MessageType::kPong));
  return protocol::decode_pong(payload());
}
Result<protocol::FrameImage> Message::frame_image() const {
  TLV_TRY(expect(protocol::MessageType::kFrameImage));
  return protocol::decode_frame_image(payload());
}

}  // namespace tlvlink::listen
