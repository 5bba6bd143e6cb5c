#pragma once
// How a host puts board timestamps on its own clock (README "Clock offset"). The host sends
// Ping/TimeSync commands; each answering Pong gives one NTP-style exchange:
//   t1 host send (the command's header send_ns), t2 board receive, t3 board send (the Pong's
//   header send_ns), t4 host receive;
//   offset = ((t2 - t1) + (t3 - t4)) / 2   (board clock - host clock)
//   delay  = (t4 - t1) - (t3 - t2)         (round trip spent on the link)
// The true offset lies within offset +- delay / 2. ClockSync keeps the last kWindow exchanges
// and uses the one with the smallest delay (the least queueing), widening its bound by a drift
// allowance as it ages. Pure arithmetic: no clock reads, no allocation.

#include <array>
#include <cstddef>
#include <cstdint>

namespace tlvlink::protocol {

struct ClockSample {
  int64_t t1 = 0, t2 = 0, t3 = 0, t4 = 0;
};

struct ClockEstimate {
  bool valid = false;
  int64_t offset_ns = 0;  // board clock - host clock
  int64_t uncertainty_ns =
      0;                 // |true offset - offset_ns| <= uncertainty_ns (drift allowance included)
  int64_t delay_ns = 0;  // round-trip delay of the sample used
  size_t samples = 0;    // exchanges in the window
};

class ClockSync {
 public:
  static constexpr size_t kWindow = 8;
  // Two independent crystal clocks drift apart by up to ~100 ppm (50 ppm parts, both ends):
  // an estimate's bound grows by this much per second of age.
  static constexpr int64_t kDriftPartsPerMillion = 100;

  // Adds one exchange; false (and ignored) when its timestamps are inconsistent: t4 < t1,
  // t3 < t2, or a negative delay (the board took longer than the round trip).
  bool add(const ClockSample& sample);
  // The estimate at host time now_ns (for the drift allowance). Not valid before the first sample.
  ClockEstimate estimate(int64_t now_ns) const;
  // Board timestamp -> host clock with the current estimate (unchanged when there is none).
  int64_t board_to_host(int64_t board_ns) const;
  int64_t host_to_board(int64_t host_ns) const;
  // Forget everything (the board restarted: its clock may have jumped).
  void reset();

 private:
  struct Entry {
    int64_t offset, delay, t4;
  };
  std::array<Entry, kWindow> entries_{};
  size_t count_ = 0, next_ = 0;
  int64_t best_offset_ = 0;
  bool have_ = false;
  void refresh();
};

}  // namespace tlvlink::protocol
