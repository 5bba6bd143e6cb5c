#pragma once
// What `tlvlink listen` and `tlvlink replay` do, as a library function (the commands only parse
// flags): run a Client, print every message (text or JSON lines), send the given commands once
// the board has said hello, report link events and, at the end, the link statistics.

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/listen/client.h"

namespace tlvlink::listen {

struct SessionOptions {
  std::string source;                 // Client::open()'s source string
  ClientOptions client;
  bool json = false;                  // JSON lines instead of text lines
  std::vector<std::string> commands;  // command_text.h syntax, sent after the first Hello
  bool stdin_commands = false;        // also read commands from stdin, one per line
  bool exit_after_replies = false;    // stop once every command was answered (1 if one was refused)
  int64_t duration_ms = -1;           // stop after this long (negative: no limit)
  uint64_t max_predictions = 0;       // stop after this many FramePredictions (0: no limit)
  int stats_every_ms = 0;             // also print the link statistics this often (0: only at the end)
  int reply_timeout_ms = 5000;        // exit_after_replies: give up waiting after this long
};

// Prints messages to `out`, events and statistics to `log`. Returns the exit code: 0, or 1 when
// a command was refused or unanswered, or the source failed for good.
Result<int> run_session(const SessionOptions& options, std::FILE* out, std::FILE* log,
                        const std::atomic<bool>& stop);

}  // namespace tlvlink::listen
