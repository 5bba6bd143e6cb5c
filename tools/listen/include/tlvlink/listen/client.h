#pragma once
// The C++ client of the prediction stream, for robot software on the host: opens the board's
// link (serial / CDC-ACM, USB bulk through libusb, or a recording), reconnects by itself when the
// link goes and comes back, keeps the board's clock offset (Ping/Pong, clock.h), counts what the
// link lost or corrupted, and hands over typed messages through a pull API (next) or callbacks
// (run). It sends Info when no Hello came within 300 ms of connecting (a reader that restarts on
// a CDC-ACM link the board never saw go down) and TimeSync once a second; the replies to those
// are consumed here, the Hello is delivered.
//
//   auto client = listen::Client::open("serial:/dev/ttyACM0").value();
//   while (auto m = client->next(1000)) {                   // Result<optional<Message>>
//     if (!m.value()) continue;                               // timeout
//     if (auto f = m.value()->frame_prediction(); f.ok())
//       use(f.value().sensor(), client->board_to_host_ns(f.value().timing().capture_ns));
//   }
//
// Threading: next()/run() on one thread; send(), stats(), clock() from any thread.

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/listen/link_stats.h"
#include "tlvlink/listen/message.h"
#include "tlvlink/protocol/messages.h"

namespace tlvlink::listen {

class RecordSink;  // recording.h
class RecordSource;

struct ClientOptions {
  bool reconnect = true;       // reopen after a disconnect or a failed open (live sources)
  int reconnect_min_ms = 100;  // backoff doubles up to the max
  int reconnect_max_ms = 1000;
  int time_sync_ms = 1000;        // TimeSync period; 0: none (no clock offset, no latencies)
  bool request_info = true;       // send Info when no Hello came soon after connecting
  std::string record;             // also write what arrives into this recording file
  bool overwrite_record = false;  // replace an existing `record` file (else it is an error)
  bool realtime = false;          // replay: pace records at their recorded times
  // Borrowed for the client's lifetime: also (or instead of `record`) receives every record a
  // .tlvrec would get, from a live source or copied from a replayed one (tools/foxglove's MCAP
  // recordings carry them). A write error ends the client as a `record` write error does.
  RecordSink* record_sink = nullptr;
};

struct LinkEvent {
  enum class Kind { kConnected, kDisconnected, kVersionMismatch, kBoardRestarted, kEndOfRecording };
  Kind kind;
  std::string text;
  int64_t time_ns = 0;
};
const char* link_event_name(LinkEvent::Kind kind);

class Client {
 public:
  // Sources: "serial:PATH[,baud=N][,flow=none|rtscts]" (a UART, /dev/ttyACM0, a pty link),
  // "usb[:VID:PID][,serial=S]" (libusb; defaults 1d6b:0104), "replay:FILE".
  // A live source that is absent is not an error here (the client keeps trying); a malformed
  // source string or an unreadable recording is.
  static Result<std::unique_ptr<Client>> open(std::string_view source,
                                              const ClientOptions& options = {});
  // A replay of records from any container (an MCAP recording's record channel); `name` is the
  // source() string.
  static Result<std::unique_ptr<Client>> open_replay(std::unique_ptr<RecordSource> records,
                                                     std::string name,
                                                     const ClientOptions& options = {});
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // The next message, waiting up to timeout_ms: nullopt on timeout or at the end of a
  // recording (ended() then true). An error only when the source cannot be used at all (a live
  // source with reconnect off that failed, a recording that broke).
  Result<std::optional<Message>> next(int timeout_ms);

  struct Handlers {
    std::function<void(const Message&)> on_message;
    std::function<void(const LinkEvent&)> on_event;
  };
  // Calls the handlers until *stop is true, duration_ms passed (negative: no limit) or the
  // recording ended.
  Status run(const Handlers& handlers, const std::atomic<bool>* stop = nullptr,
             int64_t duration_ms = -1);

  // Link events since the last call (pull API users; run() reports them through on_event).
  std::vector<LinkEvent> take_events();

  // Sends a command (any thread); returns its sequence number, which the Ack/Nack/Pong names.
  // kTransportUnavailable while the link is down; kInvalidState on a recording.
  Result<uint32_t> send(const protocol::Command& command);

  bool ended() const;
  LinkStats stats() const;
  protocol::ClockEstimate clock() const;
  // A board timestamp on the host's CLOCK_MONOTONIC (unchanged until the first Pong).
  int64_t board_to_host_ns(int64_t board_ns) const;
  int64_t host_to_board_ns(int64_t host_ns) const;
  // The board's last Hello (nullopt before one arrived).
  std::optional<Message> hello() const;
  std::string_view source() const;

 private:
  struct Impl;
  explicit Client(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace tlvlink::listen
