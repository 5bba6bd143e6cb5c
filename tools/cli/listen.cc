// tlvlink listen / tlvlink replay: the prediction stream on the host (tools/listen does the work).

#include <csignal>
#include <cstdio>

#include "common.h"
#include "record_stream.h"
#include "tlvlink/foxglove/frame_images.h"
#include "tlvlink/foxglove/session.h"
#include "tlvlink/listen/session.h"

namespace tlvlink::cli {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop = true; }

struct ListenFlags {
  std::string serial, usb, source, record, foxglove;
  int baud = 0;
  std::string flow = "none";
  bool json = false, overwrite = false, no_reconnect = false, no_time_sync = false,
       stdin_commands = false, exit_after_replies = false;
  std::vector<std::string> commands;
  double duration_s = -1, stats_every_s = 0, reply_timeout_s = 5, foxglove_wait_s = 0;
  uint64_t count = 0;
  size_t foxglove_queue = 1024;
};

void add_output_flags(CLI::App& cmd, ListenFlags& f) {
  cmd.add_flag("--json", f.json,
               "One JSON object per message (keys: tools/listen/README.md) instead of text lines");
  cmd.add_option("--duration", f.duration_s, "Stop after this many seconds");
  cmd.add_option("--count", f.count, "Stop after this many frame predictions");
  cmd.add_option("--stats-every", f.stats_every_s,
                 "Also print the link statistics every this many seconds");
  auto* fox = cmd.add_option("--foxglove", f.foxglove,
                             "Serve the messages to Foxglove (WebSocket protocol) on [HOST:]PORT "
                             "(default 127.0.0.1:8765; "
                             "PORT 0: any free port)")
                  ->expected(0, 1)
                  ->default_str("127.0.0.1:8765");
  cmd.add_option("--foxglove-wait", f.foxglove_wait_s,
                 "Before starting, wait up to this many seconds for a Foxglove client subscribed "
                 "to every channel")
      ->needs(fox);
  cmd.add_option("--foxglove-queue", f.foxglove_queue,
                 "Messages queued per Foxglove client before the oldest is dropped (a slow client)")
      ->needs(fox);
}

// --record / --overwrite / --foxglove as the library's outputs (a bare --foxglove takes the default
// address).
foxglove::SessionOutputs outputs(const ListenFlags& f, const CLI::App& cmd) {
  foxglove::SessionOutputs o;
  o.record = f.record;
  o.overwrite = f.overwrite;
  if (cmd.count("--foxglove") > 0) o.foxglove = f.foxglove.empty() ? "127.0.0.1:8765" : f.foxglove;
  o.foxglove_wait_ms = static_cast<int>(f.foxglove_wait_s * 1000);
  o.foxglove_queue = f.foxglove_queue;
  return o;
}

int run(const listen::SessionOptions& options, const foxglove::SessionOutputs& outputs,
        const char* command) {
  g_stop = false;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  Result<int> r = foxglove::run_session_with_outputs(options, outputs, stdout, stderr, g_stop);
  if (!r.ok()) return report_error(command, r.error());
  return r.value();
}

listen::SessionOptions session(const ListenFlags& f) {
  listen::SessionOptions o;
  o.json = f.json;
  o.duration_ms = f.duration_s < 0 ? -1 : static_cast<int64_t>(f.duration_s * 1000);
  o.max_predictions = f.count;
  o.stats_every_ms = static_cast<int>(f.stats_every_s * 1000);
  return o;
}

}  // namespace

void add_listen_command(CLI::App& app, int& exit_code) {
  auto f = std::make_shared<ListenFlags>();
  CLI::App* cmd = app.add_subcommand(
      "listen", "Receive the board's prediction stream (serial, CDC-ACM, USB bulk)");
  auto* serial =
      cmd->add_option("--serial", f->serial, "Serial device: a UART, /dev/ttyACM0, a pty link");
  cmd->add_option("--baud", f->baud, "Baud rate (UARTs; CDC-ACM and ptys ignore it)")
      ->needs(serial);
  cmd->add_option("--flow", f->flow, "Flow control")
      ->check(CLI::IsMember({"none", "rtscts"}))
      ->needs(serial);
  auto* usb = cmd->add_option("--usb", f->usb, "USB bulk: VID:PID[,serial=S] (default 1d6b:0104)")
                  ->expected(0, 1)
                  ->default_str("");
  auto* source = cmd->add_option("--source", f->source,
                                 "A source string: serial:PATH[,baud=N], usb[:VID:PID][,serial=S]");
  serial->excludes(usb)->excludes(source);
  usb->excludes(source);
  cmd->add_option("--record", f->record,
                  "Also record everything received into FILE (replay it with tlvlink replay): "
                  "FILE.mcap is an MCAP "
                  "file Foxglove opens; any other name a .tlvrec");
  cmd->add_flag("--overwrite", f->overwrite, "Replace an existing --record file");
  cmd->add_option("--command,-c", f->commands,
                  "Send a command once the board said hello (repeatable): start [S], stop [S], "
                  "closed ID, lifting ID, "
                  "rezero [S], set KEY=VALUE, info, ping, time_sync");
  cmd->add_flag("--stdin-commands", f->stdin_commands,
                "Also send commands typed on stdin, one per line");
  cmd->add_flag("--exit-after-replies", f->exit_after_replies,
                "Exit once every --command was answered (exit 1 if one was refused or unanswered)");
  cmd->add_option("--reply-timeout", f->reply_timeout_s,
                  "Seconds to wait for the replies (with --exit-after-replies)");
  cmd->add_flag("--no-reconnect", f->no_reconnect,
                "Fail instead of waiting for an absent or lost link");
  cmd->add_flag("--no-time-sync", f->no_time_sync,
                "Do not estimate the board's clock (no TimeSync pings)");
  add_output_flags(*cmd, *f);
  cmd->footer(std::string(kExitCodeFooter) +
              "\nMessages go to stdout; link events and statistics to stderr.");
  cmd->callback([f, usb, cmd, &exit_code] {
    listen::SessionOptions o = session(*f);
    if (!f->serial.empty()) {
      o.source = "serial:" + f->serial + (f->baud ? ",baud=" + std::to_string(f->baud) : "") +
                 (f->flow != "none" ? ",flow=" + f->flow : "");
    } else if (usb->count() > 0) {
      o.source = f->usb.empty() ? "usb" : "usb:" + f->usb;
    } else if (!f->source.empty()) {
      o.source = f->source;
    } else {
      exit_code = report_error("listen", Error(ErrorCode::kInvalidArgument,
                                               "give --serial PATH, --usb [VID:PID] or --source"));
      return;
    }
    o.client.reconnect = !f->no_reconnect;
    o.client.time_sync_ms = f->no_time_sync ? 0 : 1000;
    o.commands = f->commands;
    o.stdin_commands = f->stdin_commands;
    o.exit_after_replies = f->exit_after_replies;
    o.reply_timeout_ms = static_cast<int>(f->reply_timeout_s * 1000);
    exit_code = run(o, outputs(*f, *cmd), "listen");
  });
}

Result<record::RecordReport> record_stream_images(const std::string& stream, int32_t sensor,
                                                  const record::RecordOptions& options,
                                                  const std::string& out_path) {
  TLV_ASSIGN_OR_RETURN(record::JpegFrameSource frames,
                       foxglove::stream_frame_images(stream, sensor));
  return record::record_jpeg_frames(std::move(frames), options, out_path);
}

void add_replay_command(CLI::App& app, int& exit_code) {
  auto f = std::make_shared<ListenFlags>();
  auto realtime = std::make_shared<bool>(false);
  auto file = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "replay", "Replay a recording (tlvlink listen --record) through the same decoder");
  cmd->add_option("file", *file, "Recording file (.tlvrec, or .mcap from tlvlink listen --record)")
      ->required();
  cmd->add_flag("--realtime", *realtime, "Pace the records at their recorded times");
  cmd->add_option("--record", f->record,
                  "Also write the replay into FILE.mcap (an MCAP file Foxglove opens)");
  cmd->add_flag("--overwrite", f->overwrite, "Replace an existing --record file");
  add_output_flags(*cmd, *f);
  cmd->footer(std::string(kExitCodeFooter) +
              "\nMessages go to stdout; link events and statistics to stderr.");
  cmd->callback([f, file, realtime, cmd, &exit_code] {
    listen::SessionOptions o = session(*f);
    o.client.realtime = *realtime;
    foxglove::SessionOutputs out = outputs(*f, *cmd);
    out.replay = *file;
    exit_code = run(o, out, "replay");
  });
}

}  // namespace tlvlink::cli
