#pragma once
// `tlvlink listen` / `tlvlink replay` with their outputs: a recording (.tlvrec, or .mcap chosen
// by the extension), a Foxglove WebSocket server, and replaying either kind of recording. The
// commands parse flags and call run_session_with_outputs; listen::run_session does the rest.

#include <atomic>
#include <cstdio>
#include <string>

#include "tlvlink/error.h"
#include "tlvlink/listen/session.h"

namespace tlvlink::foxglove {

struct SessionOutputs {
  std::string record;      // FILE.mcap: an MCAP recording; any other name: a .tlvrec (live only)
  bool overwrite = false;  // replace an existing `record`
  std::string replay;      // replay this recording (.mcap or .tlvrec) instead of options.source
  std::string foxglove;    // "[HOST:]PORT": serve the messages to Foxglove ("" : no server)
  int foxglove_wait_ms =
      0;  // before the session starts, wait this long for a client subscribed to every channel
  size_t foxglove_queue = 1024;  // per client, before the oldest is dropped
};

// Runs listen::run_session with the outputs. On stderr (`log`): "foxglove: serving on
// HOST:PORT" once the server listens (tests wait for it), and at the end what was served and
// dropped, and what was recorded. Exit code as run_session's; 1 also when the MCAP recording
// could not be completed (the write error is printed).
Result<int> run_session_with_outputs(listen::SessionOptions options, const SessionOutputs& outputs,
                                     std::FILE* out, std::FILE* log, const std::atomic<bool>& stop);

}  // namespace tlvlink::foxglove
