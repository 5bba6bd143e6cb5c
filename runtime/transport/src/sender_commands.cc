// The Sender's answers to host commands (README "Commands").
#include "sender_link.h"
#include "tlvlink/protocol/names.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::transport {

void Sender::Link::on_command(const protocol::FrameHeader& header,
                              std::span<const std::byte> payload, int64_t received_ns) {
  using protocol::CommandKind;
  const uint32_t seq = header.sequence;
  Result<protocol::Command> decoded = protocol::decode_command(payload);
  auto refuse = [&](CommandKind kind, const Error& e) {
    {
      std::lock_guard lock(s_.mutex_);
      ++s_.counters_.commands_refused;
    }
    reply(protocol::Nack{seq, kind, static_cast<uint16_t>(e.code()), e.message()});
  };
  {
    std::lock_guard lock(s_.mutex_);
    ++s_.counters_.commands;
  }
  if (!decoded.ok()) {
    refuse(CommandKind::kNone, decoded.error());
    return;
  }
  const protocol::Command& c = decoded.value();
  switch (c.kind) {
    case CommandKind::kTimeSync:
      if (c.clock_uncertainty_ns > 0) {
        std::lock_guard lock(s_.mutex_);
        s_.host_clock_ =
            protocol::ClockEstimate{true, c.clock_offset_ns, c.clock_uncertainty_ns, 0, 0};
      }
      [[fallthrough]];
    case CommandKind::kPing:
      // t1 = the command's send time, t2 = now-ish (when its bytes were read); t3 is stamped
      // into the Pong's header when it is written.
      reply(protocol::Pong{seq, header.send_ns, received_ns});
      return;
    case CommandKind::kInfo:
      reply_hello();
      reply(protocol::Ack{seq, c.kind});
      return;
    case CommandKind::kStart:
    case CommandKind::kStop:
    case CommandKind::kGraspClosed:
    case CommandKind::kGraspLifting:
    case CommandKind::kRezero:
    case CommandKind::kSetConfig: {
      // Set before start() and never changed after: read without the lock, not copied.
      const CommandHandler& handler = s_.handler_;
      if (!handler) {
        refuse(c.kind, Error::make(ErrorCode::kProtocolUnsupported,
                                   "this board does not handle '%s' commands",
                                   protocol::command_kind_name(c.kind)));
        return;
      }
      const Status st = handler(c);
      if (st.ok())
        reply(protocol::Ack{seq, c.kind});
      else
        refuse(c.kind, st.error());
      return;
    }
    case CommandKind::kNone: break;
  }
  refuse(
      c.kind,
      Error::make(ErrorCode::kProtocolUnsupported, "unknown command kind %u (protocol %u.%u)",
                  static_cast<unsigned>(c.kind), protocol::kVersionMajor, protocol::kVersionMinor));
}

}  // namespace tlvlink::transport
