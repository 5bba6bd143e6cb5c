#pragma once
// Replayable randomness for tests. Every randomized test takes its seed from test_seed():
// TLVLINK_TEST_SEED=<n> in the environment replays a run; otherwise a fixed default is used so CI
// is deterministic. SCOPED_SEED_TRACE() puts the seed and the replay command into any failure.

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace tlvlink::testing {

uint64_t test_seed();
std::string replay_hint(
    uint64_t seed);  // "replay: TLVLINK_TEST_SEED=<seed> <test binary> --gtest_filter=..."

#define SCOPED_SEED_TRACE(seed) SCOPED_TRACE(::tlvlink::testing::replay_hint(seed))

class Rng {
 public:
  explicit Rng(uint64_t seed) : engine_(seed) {}
  float uniform(float lo, float hi) {
    return std::uniform_real_distribution<float>(lo, hi)(engine_);
  }
  float normal(float mean, float stddev) {
    return std::normal_distribution<float>(mean, stddev)(engine_);
  }
  int32_t int_in(int32_t lo, int32_t hi) {  // inclusive
    return std::uniform_int_distribution<int32_t>(lo, hi)(engine_);
  }
  bool coin() { return int_in(0, 1) == 1; }
  std::vector<float> floats(size_t n, float lo, float hi);
  std::vector<int8_t> int8s(size_t n, int32_t lo = -128, int32_t hi = 127);
  std::mt19937_64& engine() { return engine_; }

 private:
  std::mt19937_64 engine_;
};

}  // namespace tlvlink::testing
