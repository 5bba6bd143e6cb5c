#include "render/rng.h"

#include <array>
#include <cmath>

namespace tlvlink::sim::internal {
namespace {

constexpr int kTableSize = 1 << kNormalTableBits;

// Inverse of the standard normal CDF by bisection on erfc (runs once, 4096 x 64 steps).
double normal_quantile(double p) {
  double lo = -10, hi = 10;
  for (int i = 0; i < 64; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

std::array<float, kTableSize> build_table() {
  std::array<double, kTableSize> q{};
  double sum_sq = 0;
  for (int i = 0; i < kTableSize / 2; ++i) {
    q[static_cast<size_t>(i)] = normal_quantile((i + 0.5) / kTableSize);
    q[static_cast<size_t>(kTableSize - 1 - i)] = -q[static_cast<size_t>(i)];  // exact symmetry
  }
  for (double v : q) sum_sq += v * v;
  // The discrete quantiles miss the far tails; rescale to unit variance exactly.
  const double scale = 1.0 / std::sqrt(sum_sq / kTableSize);
  std::array<float, kTableSize> table{};
  for (size_t i = 0; i < table.size(); ++i) table[i] = static_cast<float>(q[i] * scale);
  return table;
}

}  // namespace

const float* normal_table() {
  static const std::array<float, kTableSize> table = build_table();
  return table.data();
}

}  // namespace tlvlink::sim::internal
