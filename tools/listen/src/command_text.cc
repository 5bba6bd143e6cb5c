#include "tlvlink/listen/command_text.h"

#include <charconv>
#include <string>

#include "tlvlink/protocol/names.h"

namespace tlvlink::listen {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() &&
         (s.back() == ' ' || s.back() == '\t' || s.back() == '\n' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

template <typename T>
Result<T> number(std::string_view text, std::string_view what, uint64_t max) {
  uint64_t v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  TLV_ENSURE(r.ec == std::errc() && r.ptr == text.data() + text.size() && v <= max,
             ErrorCode::kInvalidArgument, "command: %.*s '%.*s' is not a number up to %llu",
             static_cast<int>(what.size()), what.data(), static_cast<int>(text.size()), text.data(),
             static_cast<unsigned long long>(max));
  return static_cast<T>(v);
}

}  // namespace

Result<protocol::Command> parse_command(std::string_view text) {
  using protocol::CommandKind;
  text = trim(text);
  const size_t space = text.find(' ');
  std::string_view verb = text.substr(0, space);
  const std::string_view arg =
      space == std::string_view::npos ? std::string_view() : trim(text.substr(space + 1));
  protocol::Command c;
  if (verb == "closed") verb = "grasp_closed";
  if (verb == "lifting") verb = "grasp_lifting";
  if (verb == "set") verb = "set_config";
  if (verb == "sync" || verb == "timesync") verb = "time_sync";
  const std::string verb_text(verb);
  TLV_ENSURE(!verb.empty() && protocol::command_kind_from_name(verb_text.c_str(), c.kind),
             ErrorCode::kInvalidArgument,
             "unknown command '%.*s' (start [SENSOR], stop [SENSOR], closed ID, lifting ID, rezero "
             "[SENSOR], "
             "set KEY=VALUE, info, ping, time_sync)",
             static_cast<int>(text.size()), text.data());
  switch (c.kind) {
    case CommandKind::kStart:
    case CommandKind::kStop:
    case CommandKind::kRezero: {
      if (!arg.empty()) {
        TLV_ASSIGN_OR_RETURN(c.sensor, number<uint8_t>(arg, "sensor", 254));
      }
      break;
    }
    case CommandKind::kGraspClosed:
    case CommandKind::kGraspLifting: {
      TLV_ENSURE(!arg.empty(), ErrorCode::kInvalidArgument, "command '%.*s' needs a grasp id",
                 static_cast<int>(verb.size()), verb.data());
      TLV_ASSIGN_OR_RETURN(c.grasp_id, number<uint32_t>(arg, "grasp id", 0xFFFFFFFFu));
      break;
    }
    case CommandKind::kSetConfig: {
      const size_t eq = arg.find('=');
      TLV_ENSURE(eq != std::string_view::npos && eq > 0, ErrorCode::kInvalidArgument,
                 "command 'set' needs KEY=VALUE, got '%.*s'", static_cast<int>(arg.size()),
                 arg.data());
      c.key = trim(arg.substr(0, eq));
      c.value = trim(arg.substr(eq + 1));
      break;
    }
    case CommandKind::kNone:
    case CommandKind::kInfo:
    case CommandKind::kPing:
    case CommandKind::kTimeSync:
      TLV_ENSURE(arg.empty(), ErrorCode::kInvalidArgument, "command '%.*s' takes no argument",
                 static_cast<int>(verb.size()), verb.data());
      break;
  }
  return c;
}

}  // namespace tlvlink::listen
