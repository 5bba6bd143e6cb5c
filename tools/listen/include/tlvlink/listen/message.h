#pragma once
// One message as the host received it: its header, its payload (owned, 8-byte aligned) and the
// host time it arrived. Typed access decodes (and verifies) the payload in place: the views it
// returns point into this Message and live as long as it does.

#include <cstdint>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/protocol/clock.h"
#include "tlvlink/protocol/views.h"
#include "tlvlink/protocol/wire.h"

namespace tlvlink::listen {

class Message {
 public:
  Message(const protocol::FrameHeader& header, std::span<const std::byte> payload,
          int64_t receive_ns);

  const protocol::FrameHeader& header() const { return header_; }
  protocol::MessageType type() const { return header_.type; }
  uint32_t sequence() const { return header_.sequence; }
  int64_t send_ns() const { return header_.send_ns; }  // board clock
  int64_t receive_ns() const { return receive_ns_; }   // host CLOCK_MONOTONIC (or as recorded)
  bool delayed() const { return (header_.flags & protocol::kFlagDelayed) != 0; }
  std::span<const std::byte> payload() const {
    return {reinterpret_cast<const std::byte*>(storage_.data()), size_};
  }

  // The client's clock estimate when this message arrived (valid after the first Pong; host time
  // = board time - offset_ns). A function of the stream alone, so a replay gives the same.
  const protocol::ClockEstimate& clock() const { return clock_; }
  void set_clock(const protocol::ClockEstimate& clock) { clock_ = clock; }
  int64_t to_host_ns(int64_t board_ns) const {
    return clock_.valid ? board_ns - clock_.offset_ns : board_ns;
  }

  // kInvalidState when the message is of another type; kProtocolMalformed when it does not verify.
  Result<protocol::HelloView> hello() const;
  Result<protocol::FramePredictionView> frame_prediction() const;
  Result<protocol::GraspPredictionView> grasp_prediction() const;
  Result<protocol::StatsView> stats() const;
  Result<protocol::ErrorReport> error_report() const;
  Result<protocol::Ack> ack() const;
  Result<protocol::Nack> nack() const;
  Result<protocol::Pong> pong() const;
  Result<protocol::FrameImage> frame_image() const;

 private:
  Status expect(protocol::MessageType type) const;
  protocol::FrameHeader header_;
  int64_t receive_ns_;
  protocol::ClockEstimate clock_;
  std::vector<uint64_t> storage_;
  size_t size_;
};

}  // namespace tlvlink::listen
