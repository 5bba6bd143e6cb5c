#include "tlvlink/stream/commands.h"

#include <charconv>

namespace tlvlink::stream {

bool parse_command(std::string_view line, int64_t now_ns, Command& out) {
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r' || line.back() == ' '))
    line.remove_suffix(1);
  out = Command{};
  out.t_ns = now_ns;
  if (line == "closed") {
    out.kind = CommandKind::kClosed;
    return true;
  }
  if (line == "lifting") {
    out.kind = CommandKind::kLifting;
    return true;
  }
  if (line.rfind("rezero", 0) != 0) return false;
  out.kind = CommandKind::kRezero;
  std::string_view rest = line.substr(6);
  if (rest.empty()) return true;
  if (rest.front() != ' ') return false;
  rest.remove_prefix(1);
  int32_t sensor = -1;
  const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), sensor);
  if (ec != std::errc() || end != rest.data() + rest.size() || sensor < 0) return false;
  out.sensor = sensor;
  return true;
}

Result<Command> from_protocol(const protocol::Command& c, int64_t now_ns) {
  Command cmd;
  cmd.t_ns = c.event_ns > 0 ? c.event_ns : now_ns;
  switch (c.kind) {
    case protocol::CommandKind::kGraspClosed: cmd.kind = CommandKind::kClosed; break;
    case protocol::CommandKind::kGraspLifting: cmd.kind = CommandKind::kLifting; break;
    case protocol::CommandKind::kRezero:
      cmd.kind = CommandKind::kRezero;
      cmd.sensor = c.sensor == protocol::kNoSensor ? -1 : c.sensor;
      break;
    default:
      // The Nack's text (the wire carries it; kept as the daemon has always said it).
      return Error::make(ErrorCode::kProtocolUnsupported,
                         "tlvlinkd does not take this command yet");
  }
  return cmd;
}

}  // namespace tlvlink::stream
