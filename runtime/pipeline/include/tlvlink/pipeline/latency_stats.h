#pragma once
// Latency percentiles without allocation: the last kWindow samples in a ring, plus count and
// maximum over the whole run. Percentiles are exact over the window (nth_element on a copy made
// into a buffer owned by the object). Not thread-safe: one writer, and readers on the same
// thread (the daemon's output thread owns them).

#include <array>
#include <cstdint>

namespace tlvlink::pipeline {

class LatencyStats {
 public:
  static constexpr int32_t kWindow = 4096;

  void add(int64_t ns);
  int64_t count() const { return count_; }
  int64_t max_ns() const { return max_; }
  // The q-quantile (0..1) of the window; 0 when empty.
  int64_t percentile_ns(double q) const;
  void reset();

 private:
  std::array<int64_t, kWindow> ring_{};
  mutable std::array<int64_t, kWindow> scratch_{};
  int64_t count_ = 0, max_ = 0;
  int32_t next_ = 0;
};

}  // namespace tlvlink::pipeline
