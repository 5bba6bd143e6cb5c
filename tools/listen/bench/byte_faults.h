#pragma once
// Damage to a byte stream at stated rates, from a seeded generator: each byte is dropped with
// probability `byte_drop_rate`, else replaced by a different random byte with probability
// `byte_error_rate`. One rule for every fault injector of the tests and benchmarks: the pty
// cable (pty_cable.h) and the corrupting transport (corrupting_transport.h), so the pty and USB
// corruption tables are comparable.

#include <cstddef>
#include <cstdint>
#include <random>
#include <span>

namespace tlvlink::testing {

struct ByteFaultRates {
  double byte_error_rate = 0;
  double byte_drop_rate = 0;
  uint64_t seed = 1;
};

struct ByteFaultCounts {
  uint64_t bytes = 0, corrupted = 0, dropped = 0;  // bytes seen, replaced, deleted
};

class ByteFaults {
 public:
  explicit ByteFaults(ByteFaultRates rates) : rates_(rates), rng_(rates.seed) {}

  // Copies `in` to `out` (at least in.size() bytes) with the faults applied; returns the bytes
  // written (fewer than in.size() by the drops).
  size_t apply(std::span<const std::byte> in, std::byte* out);
  const ByteFaultCounts& counts() const { return counts_; }
  const ByteFaultRates& rates() const { return rates_; }

 private:
  ByteFaultRates rates_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> uniform_{0, 1};
  std::uniform_int_distribution<int> other_{1, 255};
  ByteFaultCounts counts_;
};

}  // namespace tlvlink::testing
