#include "tlvlink/pipeline/latency_stats.h"

#include <algorithm>

namespace tlvlink::pipeline {

void LatencyStats::add(int64_t ns) {
  ring_[static_cast<size_t>(next_)] = ns;
  next_ = (next_ + 1) % kWindow;
  ++count_;
  max_ = std::max(max_, ns);
}

int64_t LatencyStats::percentile_ns(double q) const {
  const auto n = static_cast<size_t>(std::min<int64_t>(count_, kWindow));
  if (n == 0) return 0;
  std::copy_n(ring_.begin(), n, scratch_.begin());
  const auto k = static_cast<size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(n - 1) + 0.5);
  std::nth_element(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(k),
                   scratch_.begin() + static_cast<std::ptrdiff_t>(n));
  return scratch_[k];
}

void LatencyStats::reset() {
  count_ = max_ = 0;
  next_ = 0;
}

}  // namespace tlvlink::pipeline
