#include "tlvlink/foxglove/session.h"

#include "tlvlink/foxglove/mcap_recording.h"
#include "tlvlink/foxglove/server.h"

namespace tlvlink::foxglove {

Result<int> run_session_with_outputs(listen::SessionOptions options, const SessionOutputs& outputs,
                                     std::FILE* out, std::FILE* log,
                                     const std::atomic<bool>& stop) {
  if (!outputs.replay.empty()) {
    options.source = "replay:" + outputs.replay;
    if (is_mcap_path(outputs.replay)) {
      const std::string path = outputs.replay;
      options.open_client =
          [path](const listen::ClientOptions& client) -> Result<std::unique_ptr<listen::Client>> {
        TLV_ASSIGN_OR_RETURN(std::unique_ptr<McapRecordSource> records,
                             McapRecordSource::open(path));
        return listen::Client::open_replay(std::move(records), "replay:" + path, client);
      };
    }
  }
  std::unique_ptr<McapRecording> mcap;
  if (is_mcap_path(outputs.record)) {
    TLV_ASSIGN_OR_RETURN(mcap, McapRecording::create(outputs.record, outputs.overwrite));
    options.client.record_sink = mcap.get();
    options.sinks.push_back(mcap.get());
  } else if (!outputs.record.empty()) {
    TLV_ENSURE(outputs.replay.empty(), ErrorCode::kInvalidArgument,
               "--record %s with a replay: copy the file instead (or record to a .mcap)",
               outputs.record.c_str());
    options.client.record = outputs.record;
    options.client.overwrite_record = outputs.overwrite;
  }
  std::unique_ptr<Server> server;
  if (!outputs.foxglove.empty()) {
    ServerOptions so;
    TLV_ASSIGN_OR_RETURN(so.address, parse_host_port(outputs.foxglove));
    so.queue_messages = outputs.foxglove_queue;
    TLV_ASSIGN_OR_RETURN(server, Server::start(so));
    std::fprintf(log, "foxglove: serving on %s\n", server->address().c_str());
    std::fflush(log);
    if (outputs.foxglove_wait_ms > 0 &&
        !server->wait_for_full_subscriber(outputs.foxglove_wait_ms, stop)) {
      std::fprintf(log, "foxglove: no client subscribed to every channel within %d ms; going on\n",
                   outputs.foxglove_wait_ms);
    }
    options.sinks.push_back(server.get());
  }

  Result<int> result = listen::run_session(options, out, log, stop);

  if (server) {
    server->shutdown();
    const ServerCounters c = server->counters();
    std::fprintf(log,
                 "foxglove: %llu clients, %llu messages sent, %llu dropped (slow clients), %llu "
                 "bad requests\n",
                 static_cast<unsigned long long>(c.clients),
                 static_cast<unsigned long long>(c.messages_sent),
                 static_cast<unsigned long long>(c.messages_dropped),
                 static_cast<unsigned long long>(c.protocol_errors));
  }
  if (mcap) {
    // The summary is written even after an error elsewhere: what was recorded stays readable.
    // A write that failed during the session was reported there (and ended it with exit 1).
    const bool reported = mcap->failed();
    if (Status st = mcap->close(); !st.ok()) {
      if (reported) return 1;
      std::fprintf(log, "tlvlink: error [%s]: %s\n", error_code_name(st.error().code()),
                   st.error().message());
      return 1;
    }
    std::fprintf(log, "# recorded %llu MCAP messages to %s\n",
                 static_cast<unsigned long long>(mcap->message_count()), outputs.record.c_str());
  }
  return result;
}

}  // namespace tlvlink::foxglove
