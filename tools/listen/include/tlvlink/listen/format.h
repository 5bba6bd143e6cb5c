#pragma once
// How `tlvlink listen` / `tlvlink replay` print messages: one JSON object per line (the same
// keys as the Python client's Message.to_dict(); tools/listen/README.md lists them) or one
// human-readable line. The board's Hello, when known, names heads and labels; the message's
// clock estimate, when valid, adds host-clock times.

#include <optional>
#include <string>

#include "tlvlink/listen/link_stats.h"
#include "tlvlink/listen/message.h"

namespace tlvlink::listen {

struct FormatContext {
  const Message* hello = nullptr;  // the board's last Hello, if any
};

std::string json_line(const Message& message, const FormatContext& context);
std::string text_line(const Message& message, const FormatContext& context);
// Link statistics: a multi-line text summary and a JSON object.
std::string stats_text(const LinkStats& stats);
std::string stats_json(const LinkStats& stats);

}  // namespace tlvlink::listen
