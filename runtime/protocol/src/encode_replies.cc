// The small messages: ErrorReport, Ack, Nack, Pong (board -> host) and Command (host -> board).
#include "protocol_internal.h"

namespace tlvlink::protocol {
namespace {
namespace fb = tlvlink::wire;
using internal::string_or_null;
}  // namespace

Result<std::span<const std::byte>> encode_payload(const ErrorReport& m,
                                                  std::span<std::byte> buffer) {
  internal::SizeBound bound;
  bound.table(4);
  bound.string(m.name);
  bound.string(m.text);
  return internal::build_payload(
      "ErrorReport", bound, buffer, [&](flatbuffers::FlatBufferBuilder& fbb) {
        const auto name = string_or_null(fbb, m.name), text = string_or_null(fbb, m.text);
        return fb::CreateErrorReport(fbb, m.code, name, text, m.sensor);
      });
}

Result<std::span<const std::byte>> encode_payload(const Ack& m, std::span<std::byte> buffer) {
  internal::SizeBound bound;
  bound.table(2);
  return internal::build_payload("Ack", bound, buffer, [&](flatbuffers::FlatBufferBuilder& fbb) {
    return fb::CreateAck(fbb, m.command_sequence, static_cast<fb::CommandKind>(m.kind));
  });
}

Result<std::span<const std::byte>> encode_payload(const Nack& m, std::span<std::byte> buffer) {
  internal::SizeBound bound;
  bound.table(4);
  bound.string(m.text);
  return internal::build_payload("Nack", bound, buffer, [&](flatbuffers::FlatBufferBuilder& fbb) {
    const auto text = string_or_null(fbb, m.text);
    return fb::CreateNack(fbb, m.command_sequence, static_cast<fb::CommandKind>(m.kind), m.code,
                          text);
  });
}

Result<std::span<const std::byte>> encode_payload(const Pong& m, std::span<std::byte> buffer) {
  internal::SizeBound bound;
  bound.table(3);
  return internal::build_payload("Pong", bound, buffer, [&](flatbuffers::FlatBufferBuilder& fbb) {
    return fb::CreatePong(fbb, m.command_sequence, m.host_send_ns, m.board_receive_ns);
  });
}

Result<std::span<const std::byte>> encode_payload(const Command& m, std::span<std::byte> buffer) {
  internal::SizeBound bound;
  bound.table(8);
  bound.string(m.key);
  bound.string(m.value);
  return internal::build_payload(
      "Command", bound, buffer, [&](flatbuffers::FlatBufferBuilder& fbb) {
        const auto key = string_or_null(fbb, m.key), value = string_or_null(fbb, m.value);
        return fb::CreateCommand(fbb, static_cast<fb::CommandKind>(m.kind), m.sensor, m.grasp_id,
                                 m.event_ns, key, value, m.clock_offset_ns, m.clock_uncertainty_ns);
      });
}

}  // namespace tlvlink::protocol
