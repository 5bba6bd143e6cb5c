#pragma once
// The board side of the stream, as the daemon uses it: post() predictions, grasp results,
// errors and stats from any thread — never blocking on the link, never allocating — and one
// I/O thread does the rest:
//  - a bounded queue (SenderConfig::queue_bytes) between inference and the link: when the link
//    is slower than the predictions, or down, the oldest queued messages are dropped and
//    counted by cause (queue_full, link_down, stale); the next Stats carries the counts;
//  - predictions made while the link is down stay queued (up to that bound) and go out when
//    it returns, flagged kFlagDelayed;
//  - the link is reopened with backoff when the device or host comes back; every (re)connect
//    starts with a Hello;
//  - commands from the host are decoded and answered: Ping/TimeSync with a Pong, Info with the
//    Hello, the others go to the daemon's CommandHandler whose Status becomes an Ack or a Nack.
//
// Example (the daemon's output = "serial:/dev/ttyGS0"):
//   TLV_ASSIGN_OR_RETURN(auto link, transport::make_transport("serial:/dev/ttyGS0"));
//   TLV_ASSIGN_OR_RETURN(auto sender, transport::Sender::create(std::move(link), {}));
//   TLV_TRY(sender->set_hello(hello));
//   TLV_TRY(sender->set_command_handler([&](const protocol::Command& c) { return
//   pipeline.command(c); })); TLV_TRY(sender->start());
//   ... per frame:  (void)sender->post(prediction);   // protocol::FramePrediction
//   ... per second: (void)sender->post(stats);        // link counters and link drops filled in
//   sender->stop();                                   // flushes for up to flush_ms

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/protocol/clock.h"
#include "tlvlink/protocol/deframer.h"
#include "tlvlink/protocol/encode.h"
#include "tlvlink/protocol/messages.h"
#include "tlvlink/transport/send_queue.h"
#include "tlvlink/transport/transport.h"

namespace tlvlink::transport {

struct SenderConfig {
  // Bound on queued messages. With two sensors at 60 fps and ~200-byte predictions, 256 KiB
  // keeps about 9 s of predictions while the link is down (SendQueue::record_size per message).
  size_t queue_bytes = 256 * 1024;
  int64_t max_age_ms = 0;     // drop queued messages older than this when they could go (0: keep)
  int reconnect_min_ms = 50;  // backoff between reopen attempts: doubles up to the max
  int reconnect_max_ms = 1000;
  int stall_ms = 1000;  // no byte accepted for this long while data waits: the link is down
  // stop(): time allowed to send what is still queued (and for the host to take the last USB
  // transfer). 500 ms lost the last prediction on an emulated Cortex-A72 at 160 % CPU (HIL,
  // 2026-11-25): a busy board needs longer; a reader that takes nothing costs this much at stop.
  int flush_ms = 2000;
  // SCHED_FIFO priority of the link thread only (0: inherit). On a busy board the link thread's
  // wake-up dominates the added latency's tail (tools/listen/README.md "Figures"). Needs
  // CAP_SYS_NICE or an RLIMIT_RTPRIO (systemd: LimitRTPRIO=); when refused the thread runs on
  // and SenderCounters::realtime says so.
  int realtime_priority = 0;
};

struct SenderCounters {
  bool link_up = false;
  uint32_t reconnects = 0;  // link came up again after being down
  uint64_t posted = 0;      // messages given to post()
  uint64_t frames_sent = 0, bytes_sent = 0, delayed_sent = 0;
  uint64_t dropped_queue_full = 0;  // link up but slower than the predictions
  uint64_t dropped_link_down = 0;   // link down longer than the queue holds
  uint64_t dropped_stale = 0;       // older than max_age_ms
  uint64_t frames_received = 0, frames_rejected = 0;
  uint64_t commands = 0, commands_refused = 0;
  uint32_t queue_messages = 0, queue_bytes = 0, queue_capacity_bytes = 0;
  bool realtime = false;  // the link thread got its SCHED_FIFO priority
  Error link_error;       // why the link was last down (code kOk if never)
};

class Sender {
 public:
  // Called on the link thread for Start, Stop, GraspClosed, GraspLifting, Rezero, SetConfig;
  // must return quickly (hand the command to the pipeline). Ok -> Ack, an Error -> Nack with
  // its code and message.
  using CommandHandler = std::function<Status(const protocol::Command&)>;

  static Result<std::unique_ptr<Sender>> create(std::unique_ptr<Transport> transport,
                                                const SenderConfig& config);
  ~Sender();
  Sender(const Sender&) = delete;
  Sender& operator=(const Sender&) = delete;

  // Before start(): the Hello sent at every (re)connect and on Info (copied), and the handler
  // of the pipeline's commands (without one they are refused with a Nack).
  Status set_hello(const protocol::Hello& hello);
  Status set_command_handler(CommandHandler handler);
  Status start();
  // Sends what is queued for up to flush_ms while the link is up, then closes it.
  void stop();

  // Any thread; no blocking on the link, no allocation. Fails only when the message cannot be
  // encoded (too large): a full queue drops the oldest message instead.
  Status post(const protocol::FramePrediction& m);
  Status post(const protocol::GraspPrediction& m);
  Status post(const protocol::ErrorReport& m);
  Status post(const protocol::FrameImage& m);  // minor 2; posted like a prediction
  // Stats: `link` is filled in from counters() and the queue_full / link_down / stale drops are
  // appended to `drops` (the caller reports capture and inference drops). Only the newest
  // unsent Stats is kept; it goes before queued predictions.
  Status post(const protocol::Stats& m);

  SenderCounters counters() const;
  // The host's clock estimate from its last TimeSync (offset = board - host), if any.
  protocol::ClockEstimate host_clock() const;

 private:
  Sender(std::unique_ptr<Transport> transport, const SenderConfig& config);
  template <typename M>
  Status post_message(const M& m);
  class Link;  // the I/O thread's state (sender_link.cc)
  friend class Link;

  SenderConfig config_;
  std::unique_ptr<Transport> transport_;
  std::unique_ptr<Link> link_;
  std::thread thread_;
  std::atomic<bool> stopping_{false}, started_{false};

  mutable std::mutex mutex_;      // guards everything below
  std::condition_variable wake_;  // reconnect backoff sleeps on it; stop() wakes it
  SendQueue queue_;
  alignas(8) std::byte scratch_[protocol::kEncodeBufferSize];
  alignas(8) std::byte stats_payload_[protocol::kMaxPayloadSize];
  size_t stats_size_ = 0;
  bool stats_delayed_ = false;  // the newest Stats was made while the link was down
  std::vector<std::byte> hello_payload_;
  CommandHandler handler_;  // set before start(), read by the link thread without the lock
  SenderCounters counters_;
  protocol::ClockEstimate host_clock_;
};

}  // namespace tlvlink::transport
