#pragma once
// What `tlvlink listen` and `tlvlink replay` do, as a library function (the commands only parse
// flags): run a Client, print every message (text or JSON lines), send the given commands once
// the board has said hello, report link events and, at the end, the link statistics.

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/listen/client.h"
#include "tlvlink/listen/format.h"

namespace tlvlink::listen {

// Receives every message the session prints, with the same context (tools/foxglove: an MCAP
// recording, a Foxglove WebSocket server). An error ends the session with exit code 1.
class MessageSink {
 public:
  virtual ~MessageSink() = default;
  virtual Status on_message(const Message& message, const FormatContext& context) = 0;
};

struct SessionOptions {
  std::string source;  // Client::open()'s source string
  ClientOptions client;
  bool json = false;                  // JSON lines instead of text lines
  std::vector<std::string> commands;  // command_text.h syntax, sent after the first Hello
  bool stdin_commands = false;        // also read commands from stdin, one per line
  bool exit_after_replies = false;    // stop once every command was answered (1 if one was refused)
  int64_t duration_ms = -1;           // stop after this long (negative: no limit)
  uint64_t max_predictions = 0;       // stop after this many FramePredictions (0: no limit)
  int stats_every_ms = 0;       // also print the link statistics this often (0: only at the end)
  int reply_timeout_ms = 5000;  // exit_after_replies: give up waiting after this long
  std::vector<MessageSink*> sinks;  // borrowed for the call
  // Opens the client instead of Client::open(source, client) (a replay of another container).
  std::function<Result<std::unique_ptr<Client>>(const ClientOptions&)> open_client;
};

// Prints messages to `out`, events and statistics to `log`. Returns the exit code: 0, or 1 when
// a command was refused or unanswered, or the source failed for good.
Result<int> run_session(const SessionOptions& options, std::FILE* out, std::FILE* log,
                        const std::atomic<bool>& stop);

}  // namespace tlvlink::listen
