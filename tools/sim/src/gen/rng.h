#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "rng.h is internal to tools/sim: include its public headers instead"
#endif
// Counter-based seeding and a small portable generator for the dataset generators. Every random
// stream is derived from (seed, tags...) by hashing, so item i depends only on (seed, i) and can
// be generated in any order or on any thread. std:: distributions are implementation-defined,
// so the sampling below is written out to give the same values with every standard library.

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <numbers>
#include <span>

namespace tlvlink::sim::internal {

// SplitMix64's finalizer: a bijective 64-bit mix with full avalanche.
inline constexpr uint64_t mix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// A seed for the stream named by `tags` under `seed` (order matters).
inline constexpr uint64_t derive_seed(uint64_t seed, std::initializer_list<uint64_t> tags) {
  uint64_t h = mix64(seed ^ 0x6A09E667F3BCC909ull);
  for (uint64_t t : tags) h = mix64(h ^ mix64(t + 0x3C6EF372FE94F82Bull));
  return h;
}

// Stream tags, so two uses of the same (seed, index) never share a stream.
enum class Stream : uint64_t {
  kMaterial = 1,
  kSession,
  kFrame,
  kVision,
  kDescription,
  kSensor,
  kObject,
  kGrasp,
  kRender,
  kOracle,
  kHidden,
  kTexture,
  kSensorInstance,  // which sensor instance draws a session / a finger (appended: tags never move)
  kSensorProfile,   // which profile of a mixed-profile set records a session / object (appended)
  kMarkers,         // whether a session's / object's gel has markers (markers_fraction; appended)
  kLivePath,        // whether an object's frames take the live path (live_path_fraction; appended)
};
inline constexpr uint64_t tag(Stream s) { return static_cast<uint64_t>(s); }

class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}

  uint64_t next() {
    state_ += 0x9E3779B97F4A7C15ull;
    uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // log-uniform on [lo, hi], lo > 0.
  double log_uniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  // Uniform integer in [lo, hi] (inclusive); the modulo bias is < 2^-32 for our ranges.
  int32_t int_in(int32_t lo, int32_t hi) {
    const uint64_t span = static_cast<uint64_t>(static_cast<int64_t>(hi) - lo + 1);
    return static_cast<int32_t>(lo + static_cast<int64_t>(next() % span));
  }
  bool bernoulli(double p) { return uniform() < p; }
  // Standard normal (Box-Muller, one value per call).
  double normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]: log is finite
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }
  // Approximately standard normal from one draw (Irwin-Hall sum of four 16-bit uniforms):
  // cheap enough for per-pixel camera noise; tails end at +-3.5 sigma.
  double fast_normal() {
    const uint64_t r = next();
    const double sum = static_cast<double>((r & 0xFFFF) + ((r >> 16) & 0xFFFF) +
                                           ((r >> 32) & 0xFFFF) + (r >> 48)) *
                       0x1.0p-16;
    return (sum - 2.0) * 1.7320508075688772;  // sd of the sum is sqrt(4/12)
  }
  // Index drawn with probability proportional to weights[i] (>= 0); 0 if all are zero.
  size_t weighted(std::span<const double> weights) {
    double total = 0;
    for (double w : weights) total += w;
    if (!(total > 0)) return 0;
    double r = uniform() * total;
    for (size_t i = 0; i < weights.size(); ++i) {
      if (r < weights[i]) return i;
      r -= weights[i];
    }
    for (size_t i = weights.size(); i-- > 0;) {
      if (weights[i] > 0) return i;  // rounding left r >= 0 past the end
    }
    return 0;
  }

 private:
  uint64_t state_;
};

}  // namespace tlvlink::sim::internal
