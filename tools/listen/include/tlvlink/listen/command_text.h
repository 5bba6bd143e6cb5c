#pragma once
// Commands as people type them (`tlvlink listen --command ...`, the Python client's
// parse_command): "start [SENSOR]", "stop [SENSOR]", "closed GRASP_ID", "lifting GRASP_ID",
// "rezero [SENSOR]", "set KEY=VALUE", "info", "ping", "time_sync". The returned Command's key
// and value are views into `text`.

#include <string_view>

#include "tlvlink/error.h"
#include "tlvlink/protocol/messages.h"

namespace tlvlink::listen {

Result<protocol::Command> parse_command(std::string_view text);

}  // namespace tlvlink::listen
