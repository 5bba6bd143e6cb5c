#pragma once
// A controller's commands as a board's pipeline takes them: rezero (one sensor or all), grasp
// closed, grasp lifting. From the stream protocol (a host's Command message) or from a text
// line (a controller on stdin). What the board does with them, and when, is its own business.

#include <cstdint>
#include <string_view>

#include "tlvlink/error.h"
#include "tlvlink/protocol/messages.h"

namespace tlvlink::stream {

enum class CommandKind : uint8_t { kRezero, kClosed, kLifting };

struct Command {
  CommandKind kind = CommandKind::kRezero;
  int64_t t_ns = 0;     // when it was given (the board clock)
  int32_t sensor = -1;  // rezero: -1 = all
};

// "rezero [SENSOR_INDEX]", "closed", "lifting" (a trailing newline is fine). False: not a command.
bool parse_command(std::string_view line, int64_t now_ns, Command& out);

// A host's Command: the event time it gives, or `now_ns` when it gives none. The protocol's
// other commands (start, stop, set-config, ...) are kProtocolUnsupported; the Sender answers
// Ping / TimeSync / Info itself.
Result<Command> from_protocol(const protocol::Command& c, int64_t now_ns);

}  // namespace tlvlink::stream
