#pragma once
// The Sender's link thread: (re)opens the transport, writes one frame at a time (control
// replies first, then a frame cut off by a disconnect, then the newest Stats, then the queue),
// reads and answers commands, tracks whether the link is usable. Internal to tlvlink_transport.
#ifndef TLVLINK_TRANSPORT_PRIVATE
#error "sender_link.h is internal to tlvlink_transport"
#endif

#include "tlvlink/clock.h"
#include "tlvlink/protocol/deframer.h"
#include "tlvlink/transport/sender.h"

namespace tlvlink::transport {

class Sender::Link {
 public:
  explicit Link(Sender& sender);
  void run();  // until sender.stopping_, then the flush

 private:
  void step(int timeout_ms);
  void on_up();
  void go_down(const Error& why);
  void disconnect(const Error& why);
  void publish();  // link state -> sender counters
  bool has_output();
  void fill_out();
  bool take_message();  // next queued message into inflight_ (false: nothing to send)
  void encode(protocol::MessageType type, uint16_t flags, std::span<const std::byte> payload);
  void write_some();
  void read_all();
  void on_frame(const protocol::ReceivedFrame& frame, int64_t received_ns);
  void on_command(const protocol::FrameHeader& header, std::span<const std::byte> payload,
                  int64_t received_ns);
  template <typename M>
  void reply(const M& message);
  void reply_hello();
  void sleep(int ms);

  Sender& s_;
  Transport& t_;
  protocol::Deframer deframer_;
  SendQueue control_;  // replies made on this thread; cleared at each connect
  alignas(8) std::byte scratch_[protocol::kEncodeBufferSize];
  // The queued message being sent: kept until its frame is written whole, sent again (flagged
  // delayed) after a reconnect. Replies from control_ are framed straight from that queue.
  alignas(8) std::byte inflight_payload_[protocol::kMaxPayloadSize];
  size_t inflight_size_ = 0;
  protocol::MessageType inflight_type_ = protocol::MessageType::kHello;
  uint16_t inflight_flags_ = 0;
  bool inflight_ = false;
  std::byte out_[protocol::kMaxWireFrameSize];
  size_t out_len_ = 0, out_pos_ = 0;
  bool out_is_frame_ = false, out_is_control_ = false;
  std::byte rx_[4096];
  uint32_t sequence_ = 0;
  bool up_ = false, stalled_ = false, ever_up_ = false, version_reported_ = false;
  bool no_reader_reported_ = false;
  int64_t last_progress_ns_ = 0;
  int backoff_ms_;
  Error down_reason_;
};

// A reply made on the link thread (Ack, Nack, Pong, ErrorReport): queued on the control lane.
template <typename M>
void Sender::Link::reply(const M& message) {
  Result<std::span<const std::byte>> p = protocol::encode_payload(message, scratch_);
  if (p.ok())
    (void)control_.push(protocol::MessageTypeOf<M>::value, 0, board_clock_ns(), p.value());
}

}  // namespace tlvlink::transport
