#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "augment_rng.h is internal to tools/trainer: include its public headers instead"
#endif
// The augmentations' random draws: splitmix64 streams, so every draw is a function of a seed
// (runs and resumes stay bit-identical) and nothing is shared between threads.

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace tlvlink::trainer::rng {

inline uint64_t splitmix(uint64_t& state) {
  uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

inline double uniform01(uint64_t& state) {
  return static_cast<double>(splitmix(state) >> 11) * 0x1.0p-53;
}

inline double uniform(uint64_t& state, double lo, double hi) {
  return lo + (hi - lo) * uniform01(state);
}

// An integer in [lo, hi].
inline int32_t uniform_int(uint64_t& state, int32_t lo, int32_t hi) {
  const auto span = static_cast<uint64_t>(hi - lo + 1);
  return lo + static_cast<int32_t>(splitmix(state) % span);
}

inline bool chance(uint64_t& state, double p) { return uniform01(state) < p; }

// Box-Muller; one normal per call (the second is dropped: simplicity over speed here).
inline double normal(uint64_t& state) {
  const double u1 = std::max(uniform01(state), 1e-300), u2 = uniform01(state);
  return std::sqrt(-2 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

}  // namespace tlvlink::trainer::rng
