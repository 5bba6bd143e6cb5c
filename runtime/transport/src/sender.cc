// Sender: the producer side (post from any thread) and the thread's lifecycle. The link thread
// itself is sender_link.cc.
#include "tlvlink/transport/sender.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>

#include "sender_link.h"
#include "tlvlink/clock.h"

namespace tlvlink::transport {

Sender::Sender(std::unique_ptr<Transport> transport, const SenderConfig& config)
    : config_(config), transport_(std::move(transport)), queue_(config.queue_bytes) {
  counters_.queue_capacity_bytes = static_cast<uint32_t>(queue_.capacity());
  // Down until the link thread has opened the link and found a reader.
  counters_.link_error = Error(ErrorCode::kTransportUnavailable, "not connected yet");
}

Result<std::unique_ptr<Sender>> Sender::create(std::unique_ptr<Transport> transport,
                                               const SenderConfig& config) {
  TLV_ENSURE(transport != nullptr, ErrorCode::kInvalidArgument, "sender: no transport");
  TLV_ENSURE(config.queue_bytes >= SendQueue::record_size(protocol::kMaxPayloadSize),
             ErrorCode::kInvalidArgument,
             "sender: queue_bytes %zu cannot hold one largest message (%zu bytes)",
             config.queue_bytes, SendQueue::record_size(protocol::kMaxPayloadSize));
  TLV_ENSURE(config.reconnect_min_ms > 0 && config.reconnect_max_ms >= config.reconnect_min_ms &&
                 config.stall_ms > 0 && config.flush_ms >= 0 && config.max_age_ms >= 0 &&
                 config.realtime_priority >= 0 && config.realtime_priority <= 99,
             ErrorCode::kInvalidArgument, "sender: timing settings out of range");
  std::unique_ptr<Sender> s(new Sender(std::move(transport), config));
  s->link_ = std::make_unique<Link>(*s);
  return s;
}

Sender::~Sender() { stop(); }

Status Sender::set_hello(const protocol::Hello& hello) {
  TLV_ENSURE(!started_, ErrorCode::kInvalidState, "sender: set_hello() after start()");
  std::lock_guard lock(mutex_);
  TLV_ASSIGN_OR_RETURN(const std::span<const std::byte> payload,
                       protocol::encode_payload(hello, scratch_));
  hello_payload_.assign(payload.begin(), payload.end());
  return Status();
}

Status Sender::set_command_handler(CommandHandler handler) {
  TLV_ENSURE(!started_, ErrorCode::kInvalidState, "sender: set_command_handler() after start()");
  handler_ = std::move(handler);
  return Status();
}

Status Sender::start() {
  TLV_ENSURE(!started_.exchange(true), ErrorCode::kInvalidState, "sender: already started");
  thread_ = std::thread([this] { link_->run(); });
  if (config_.realtime_priority > 0) {
    sched_param param{};
    param.sched_priority = config_.realtime_priority;
    const bool applied = pthread_setschedparam(thread_.native_handle(), SCHED_FIFO, &param) == 0;
    std::lock_guard lock(mutex_);
    counters_.realtime = applied;
  }
  return Status();
}

void Sender::stop() {
  if (!started_ || stopping_.exchange(true)) return;
  {
    std::lock_guard lock(mutex_);
    wake_.notify_all();
  }
  transport_->interrupt();
  if (thread_.joinable()) thread_.join();
}

template <typename M>
Status Sender::post_message(const M& m) {
  {
    std::lock_guard lock(mutex_);
    TLV_ASSIGN_OR_RETURN(const std::span<const std::byte> payload,
                         protocol::encode_payload(m, scratch_));
    const bool up = counters_.link_up;
    TLV_ASSIGN_OR_RETURN(const size_t dropped,
                         queue_.push(protocol::MessageTypeOf<M>::value,
                                     up ? 0 : protocol::kFlagDelayed, board_clock_ns(), payload));
    (up ? counters_.dropped_queue_full : counters_.dropped_link_down) += dropped;
    ++counters_.posted;
  }
  transport_->interrupt();
  return Status();
}

Status Sender::post(const protocol::FramePrediction& m) { return post_message(m); }
Status Sender::post(const protocol::GraspPrediction& m) { return post_message(m); }
Status Sender::post(const protocol::ErrorReport& m) { return post_message(m); }
Status Sender::post(const protocol::FrameImage& m) { return post_message(m); }

Status Sender::post(const protocol::Stats& m) {
  constexpr size_t kOwnCauses = 3;
  TLV_ENSURE(m.drops.size() + kOwnCauses <= protocol::kMaxListLength, ErrorCode::kInvalidArgument,
             "stats: too many drop counts (%zu)", m.drops.size());
  {
    std::lock_guard lock(mutex_);
    protocol::DropCount drops[protocol::kMaxListLength];
    std::copy(m.drops.begin(), m.drops.end(), drops);
    size_t n = m.drops.size();
    // One entry per (cause, sensor): the link's own counts are added to the caller's of the same
    // cause (a board's output queue and this queue are both "queue_full").
    const auto add = [&](protocol::DropCause cause, uint64_t count) {
      for (size_t i = 0; i < n; ++i) {
        if (drops[i].cause == cause && drops[i].sensor == protocol::kNoSensor) {
          drops[i].count += count;
          return;
        }
      }
      drops[n++] = {cause, count, protocol::kNoSensor};
    };
    add(protocol::DropCause::kQueueFull, counters_.dropped_queue_full);
    add(protocol::DropCause::kLinkDown, counters_.dropped_link_down);
    add(protocol::DropCause::kStale, counters_.dropped_stale);
    // Made while the link is down: DELAYED when it goes out, even after a reconnect.
    stats_delayed_ = !counters_.link_up;
    protocol::Stats s = m;
    s.drops = std::span<const protocol::DropCount>(drops, n);
    s.link.link_up = counters_.link_up;
    s.link.reconnects = counters_.reconnects;
    s.link.frames_sent = counters_.frames_sent;
    s.link.bytes_sent = counters_.bytes_sent;
    s.link.frames_received = counters_.frames_received;
    s.link.frames_rejected = counters_.frames_rejected;
    s.link.queue_messages = static_cast<uint32_t>(queue_.size());
    s.link.queue_bytes = static_cast<uint32_t>(queue_.bytes());
    s.link.queue_capacity_bytes = static_cast<uint32_t>(queue_.capacity());
    TLV_ASSIGN_OR_RETURN(const std::span<const std::byte> payload,
                         protocol::encode_payload(s, scratch_));
    std::copy(payload.begin(), payload.end(), stats_payload_);
    stats_size_ = payload.size();
    ++counters_.posted;
  }
  transport_->interrupt();
  return Status();
}

SenderCounters Sender::counters() const {
  std::lock_guard lock(mutex_);
  SenderCounters c = counters_;
  c.queue_messages = static_cast<uint32_t>(queue_.size());
  c.queue_bytes = static_cast<uint32_t>(queue_.bytes());
  return c;
}

protocol::ClockEstimate Sender::host_clock() const {
  std::lock_guard lock(mutex_);
  return host_clock_;
}

}  // namespace tlvlink::transport
