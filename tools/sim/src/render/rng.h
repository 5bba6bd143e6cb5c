#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "rng.h is internal to tools/sim: include its public headers instead"
#endif
// Small, fast, reproducible randomness for the renderer: a stateless 64-bit hash (lattice values
// of the texture, per-sensor draws), xoshiro256** for the camera noise stream, and a table of
// unit-normal samples indexed by 12 random bits (no per-pixel log/sqrt/cos).

#include <cstdint>

namespace tlvlink::sim::internal {

// SplitMix64 finaliser: a good avalanche hash of one 64-bit word.
inline uint64_t mix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline uint64_t hash3(uint64_t seed, int64_t a, int64_t b) {
  return mix64(seed ^ mix64(static_cast<uint64_t>(a) * 0xD6E8FEB86659FD93ull ^
                            static_cast<uint64_t>(b) * 0xA0761D6478BD642Full));
}

// Uniform in [-1, 1) from the top 24 bits of a hash.
inline float hash_to_signed_unit(uint64_t h) {
  return static_cast<float>(h >> 40) * (2.0f / 16777216.0f) - 1.0f;
}

class Xoshiro256 {
 public:
  explicit Xoshiro256(uint64_t seed) {
    for (auto& w : s_) {
      seed += 0x9E3779B97F4A7C15ull;
      w = mix64(seed);
    }
  }
  uint64_t next() {
    const uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  // Uniform double in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  uint64_t s_[4];
};

// 4096 unit-variance normal samples at the quantiles (i + 0.5) / 4096; built once, thread-safe.
inline constexpr int kNormalTableBits = 12;
const float* normal_table();

}  // namespace tlvlink::sim::internal
