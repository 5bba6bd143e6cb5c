#include "tlvlink/protocol/clock.h"

namespace tlvlink::protocol {

bool ClockSync::add(const ClockSample& s) {
  if (s.t4 < s.t1 || s.t3 < s.t2) return false;
  const int64_t delay = (s.t4 - s.t1) - (s.t3 - s.t2);
  if (delay < 0) return false;
  // Halves before adding: timestamps near the int64 range cannot overflow the sum.
  const int64_t offset = (s.t2 - s.t1) / 2 + (s.t3 - s.t4) / 2;
  entries_[next_] = Entry{offset, delay, s.t4};
  next_ = (next_ + 1) % kWindow;
  if (count_ < kWindow) ++count_;
  refresh();
  return true;
}

void ClockSync::refresh() {
  size_t best = 0;
  for (size_t i = 1; i < count_; ++i) {
    if (entries_[i].delay < entries_[best].delay) best = i;
  }
  best_offset_ = entries_[best].offset;
  have_ = count_ > 0;
}

ClockEstimate ClockSync::estimate(int64_t now_ns) const {
  ClockEstimate e;
  if (!have_) return e;
  size_t best = 0;
  for (size_t i = 1; i < count_; ++i) {
    if (entries_[i].delay < entries_[best].delay) best = i;
  }
  const Entry& b = entries_[best];
  const int64_t age = now_ns > b.t4 ? now_ns - b.t4 : 0;
  e.valid = true;
  e.offset_ns = b.offset;
  // +1: the halving in add() can lose one nanosecond.
  e.uncertainty_ns = b.delay / 2 + 1 + age / 1'000'000 * kDriftPartsPerMillion;
  e.delay_ns = b.delay;
  e.samples = count_;
  return e;
}

int64_t ClockSync::board_to_host(int64_t board_ns) const {
  return have_ ? board_ns - best_offset_ : board_ns;
}
int64_t ClockSync::host_to_board(int64_t host_ns) const {
  return have_ ? host_ns + best_offset_ : host_ns;
}

void ClockSync::reset() {
  count_ = next_ = 0;
  have_ = false;
  best_offset_ = 0;
}

}  // namespace tlvlink::protocol
