#include "tlvlink/listen/link_stats.h"

#include <algorithm>
#include <cmath>

namespace tlvlink::listen {

void LatencyWindow::add(int64_t ns) {
  if (samples_.size() < kCapacity)
    samples_.push_back(ns);
  else
    samples_[next_] = ns;
  next_ = (next_ + 1) % kCapacity;
  ++total_;
  max_ = std::max(max_, ns);
}

int64_t LatencyWindow::percentile(double p) const {
  if (samples_.empty()) return 0;
  std::vector<int64_t> sorted = samples_;
  // Nearest rank: the smallest sample with at least p % of the samples at or below it.
  const size_t rank =
      static_cast<size_t>(std::ceil(p / 100.0 * static_cast<double>(sorted.size())));
  const size_t k = std::min(sorted.size() - 1, rank > 0 ? rank - 1 : 0);
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
  return sorted[k];
}

}  // namespace tlvlink::listen
