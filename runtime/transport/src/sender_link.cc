#include "sender_link.h"

#include <algorithm>

#include "tlvlink/clock.h"
#include "tlvlink/protocol/names.h"
#include "tlvlink/protocol/views.h"

namespace tlvlink::transport {
namespace {
constexpr int kWaitMs = 100;  // longest idle wait (stop() interrupts it anyway)
constexpr size_t kControlBytes = 64 * 1024;
constexpr int kReadsPerStep = 16;  // bounded so a flood of input cannot starve the writer
}  // namespace

Sender::Link::Link(Sender& sender)
    : s_(sender),
      t_(*sender.transport_),
      control_(kControlBytes),
      backoff_ms_(sender.config_.reconnect_min_ms) {
  down_reason_ = Error(ErrorCode::kTransportUnavailable, "not opened yet");
}

void Sender::Link::run() {
  while (!s_.stopping_) step(kWaitMs);
  // Flush: what is queued goes out while the link is up, for at most flush_ms.
  const int64_t deadline = board_clock_ns() + static_cast<int64_t>(s_.config_.flush_ms) * 1'000'000;
  for (int64_t now = board_clock_ns(); now < deadline && t_.is_open() && up_ && has_output();
       now = board_clock_ns()) {
    step(static_cast<int>(std::max<int64_t>(1, (deadline - now) / 1'000'000)));
  }
  if (t_.is_open() && up_) {
    const int64_t left_ms = (deadline - board_clock_ns()) / 1'000'000;
    t_.drain(static_cast<int>(std::max<int64_t>(left_ms, 0)));
  }
  t_.close();
  go_down(Error(ErrorCode::kTransportDisconnected, "sender stopped"));
}

void Sender::Link::sleep(int ms) {
  std::unique_lock lock(s_.mutex_);
  s_.wake_.wait_for(lock, std::chrono::milliseconds(ms), [&] { return s_.stopping_.load(); });
}

void Sender::Link::step(int timeout_ms) {
  if (!t_.is_open()) {
    Status opened = t_.open();
    if (!opened.ok()) {
      go_down(opened.error());
      sleep(backoff_ms_);
      backoff_ms_ = std::min(2 * backoff_ms_, s_.config_.reconnect_max_ms);
      return;
    }
    backoff_ms_ = s_.config_.reconnect_min_ms;
  }
  const bool peer = t_.peer_present();
  if (peer && !up_) on_up();
  if (!peer && (up_ || !no_reader_reported_)) {
    no_reader_reported_ = true;
    go_down(Error::make(ErrorCode::kTransportUnavailable, "no reader on %.*s",
                        static_cast<int>(t_.name().size()), t_.name().data()));
  }
  if (up_ && out_pos_ == out_len_) fill_out();
  const bool want_write = up_ && out_pos_ < out_len_;
  Result<Readiness> ready = t_.wait(want_write, timeout_ms);
  if (!ready.ok()) {
    disconnect(ready.error());
    return;
  }
  // The reader may have arrived during the wait: greet it before handling what it sent.
  if (!up_ && t_.peer_present()) on_up();
  if (ready.value().readable) read_all();
  if (!t_.is_open()) return;
  if (want_write && ready.value().writable) write_some();
  // A link that accepts nothing for stall_ms is down for accounting (drops, delayed flags), but
  // writing goes on: bytes moving again bring it back.
  const int64_t now = board_clock_ns();
  if (!want_write) {
    last_progress_ns_ = now;
  } else if (!stalled_ &&
             now - last_progress_ns_ > static_cast<int64_t>(s_.config_.stall_ms) * 1'000'000) {
    stalled_ = true;
    down_reason_ =
        Error::make(ErrorCode::kTransportUnavailable, "%.*s accepted nothing for %d ms",
                    static_cast<int>(t_.name().size()), t_.name().data(), s_.config_.stall_ms);
    publish();
  }
}

void Sender::Link::on_up() {
  up_ = true;
  no_reader_reported_ = false;
  stalled_ = false;
  last_progress_ns_ = board_clock_ns();
  version_reported_ = false;
  deframer_.reset();
  control_.clear();
  // A lone delimiter ends whatever partial frame the reader may hold; then the Hello.
  out_[0] = std::byte{0};
  out_len_ = 1, out_pos_ = 0;
  out_is_frame_ = out_is_control_ = false;
  reply_hello();
  {
    std::lock_guard lock(s_.mutex_);
    if (ever_up_) ++s_.counters_.reconnects;
  }
  ever_up_ = true;
  publish();
}

void Sender::Link::go_down(const Error& why) {
  up_ = false;
  down_reason_ = why;
  publish();
}

void Sender::Link::disconnect(const Error& why) {
  t_.close();
  // A message frame cut off mid-write stays in inflight_ and is sent again after the reconnect.
  out_len_ = out_pos_ = 0;
  go_down(why);
}

void Sender::Link::publish() {
  std::lock_guard lock(s_.mutex_);
  s_.counters_.link_up = up_ && !stalled_;
  if (!s_.counters_.link_up) s_.counters_.link_error = down_reason_;
}

bool Sender::Link::has_output() {
  if (out_pos_ < out_len_ || inflight_ || control_.size() > 0) return true;
  std::lock_guard lock(s_.mutex_);
  return s_.stats_size_ > 0 || s_.queue_.size() > 0;
}

bool Sender::Link::take_message() {
  if (inflight_) {  // cut off by a disconnect: it goes again, late
    inflight_flags_ |= protocol::kFlagDelayed;
    return true;
  }
  std::lock_guard lock(s_.mutex_);
  if (s_.stats_size_ > 0) {
    std::copy(s_.stats_payload_, s_.stats_payload_ + s_.stats_size_, inflight_payload_);
    inflight_size_ = s_.stats_size_, inflight_type_ = protocol::MessageType::kStats;
    inflight_flags_ = s_.counters_.link_up && !s_.stats_delayed_ ? 0 : protocol::kFlagDelayed;
    s_.stats_size_ = 0;
    return inflight_ = true;
  }
  const int64_t now = board_clock_ns();
  SendQueue::Record r;
  while (s_.queue_.front(r)) {
    if (s_.config_.max_age_ms > 0 && now - r.enqueue_ns > s_.config_.max_age_ms * 1'000'000) {
      s_.queue_.pop();
      ++s_.counters_.dropped_stale;
      continue;
    }
    std::copy(r.payload.begin(), r.payload.end(), inflight_payload_);
    inflight_size_ = r.payload.size(), inflight_type_ = r.type, inflight_flags_ = r.flags;
    s_.queue_.pop();
    return inflight_ = true;
  }
  return false;
}

// Order: replies made on this thread (the Hello first after a connect), then a message cut off
// by a disconnect, then the newest Stats, then the queue.
void Sender::Link::fill_out() {
  out_len_ = out_pos_ = 0;
  out_is_frame_ = out_is_control_ = false;
  SendQueue::Record r;
  if (control_.front(r)) {
    encode(r.type, r.flags, r.payload);
    control_.pop();
    out_is_control_ = true;
    return;
  }
  if (!take_message()) return;
  encode(inflight_type_, inflight_flags_,
         std::span<const std::byte>(inflight_payload_, inflight_size_));
  if (!out_is_frame_) inflight_ = false;  // could not be framed: drop it rather than loop
}

void Sender::Link::encode(protocol::MessageType type, uint16_t flags,
                          std::span<const std::byte> payload) {
  protocol::FrameHeader h;
  h.type = type;
  h.flags = flags;
  h.sequence = sequence_;
  h.send_ns = board_clock_ns();
  // Cannot fail: every payload was size-checked when it was encoded.
  Result<size_t> n = protocol::encode_frame(h, payload, out_);
  if (!n.ok()) return;
  ++sequence_;
  out_len_ = n.value();
  out_is_frame_ = true;
}

void Sender::Link::write_some() {
  Result<size_t> n = t_.write(std::span<const std::byte>(out_ + out_pos_, out_len_ - out_pos_));
  if (!n.ok()) {
    disconnect(n.error());
    return;
  }
  if (n.value() == 0) return;
  out_pos_ += n.value();
  last_progress_ns_ = board_clock_ns();
  if (stalled_) {
    stalled_ = false;
    publish();
  }
  if (out_pos_ < out_len_ || !out_is_frame_) return;
  std::lock_guard lock(s_.mutex_);
  ++s_.counters_.frames_sent;
  s_.counters_.bytes_sent += out_len_;
  if (out_is_control_) return;
  if (inflight_flags_ & protocol::kFlagDelayed) ++s_.counters_.delayed_sent;
  inflight_ = false;
}

void Sender::Link::read_all() {
  for (int i = 0; i < kReadsPerStep; ++i) {
    Result<size_t> n = t_.read(rx_);
    if (!n.ok()) {
      disconnect(n.error());
      return;
    }
    if (n.value() == 0) return;
    const int64_t received = board_clock_ns();
    deframer_.feed(std::span<const std::byte>(rx_, n.value()),
                   [&](const protocol::ReceivedFrame& f) { on_frame(f, received); });
  }
}

void Sender::Link::on_frame(const protocol::ReceivedFrame& f, int64_t received_ns) {
  {
    std::lock_guard lock(s_.mutex_);
    ++(f.verdict == protocol::FrameVerdict::kOk ? s_.counters_.frames_received
                                                : s_.counters_.frames_rejected);
  }
  if (f.verdict == protocol::FrameVerdict::kVersion && !version_reported_) {
    version_reported_ = true;  // once per connection: say it clearly, then ignore such frames
    char text[160];
    std::snprintf(
        text, sizeof(text),
        "the host speaks stream protocol %u.%u; this board speaks %u.%u: its commands are "
        "ignored (update the host client or the board)",
        f.header.version_major, f.header.version_minor, protocol::kVersionMajor,
        protocol::kVersionMinor);
    reply(protocol::ErrorReport{static_cast<uint16_t>(ErrorCode::kProtocolVersion),
                                error_code_name(ErrorCode::kProtocolVersion), text,
                                protocol::kNoSensor});
    return;
  }
  if (f.verdict != protocol::FrameVerdict::kOk) return;
  if (f.header.type == protocol::MessageType::kCommand)
    on_command(f.header, f.payload, received_ns);
  // Anything else from the host is not for the board: skipped.
}

void Sender::Link::reply_hello() {
  std::lock_guard lock(s_.mutex_);
  if (!s_.hello_payload_.empty()) {
    (void)control_.push(protocol::MessageType::kHello, 0, board_clock_ns(), s_.hello_payload_);
  }
}

}  // namespace tlvlink::transport
