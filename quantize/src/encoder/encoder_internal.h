#pragma once
#ifndef TLVLINK_QUANTIZE_PRIVATE
#error "encoder_internal.h is internal to quantize: include its public headers instead"
#endif
// Internals of the reference encoder generator.

#include <cstdint>
#include <vector>

#include "tlvlink/quantize/model_builder.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink::quantize::encoder_internal {

// splitmix64: tiny, and identical on every platform (std::*_distribution is not specified
// bit-exactly, and the same seed must give the same model on x86 and aarch64).
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  float uniform() { return static_cast<float>(next() >> 40) * 0x1p-24f; }  // [0, 1)
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  // Irwin-Hall approximation of N(0, 1): plain arithmetic, so bit-identical everywhere.
  float normal() {
    float s = 0;
    for (int i = 0; i < 12; ++i) s += uniform();
    return s - 6.0f;
  }

 private:
  uint64_t state_;
};

// Derives independent streams (weights, heads, frames) from the user's seed.
inline uint64_t derive_seed(uint64_t seed, uint64_t stream) {
  return Rng(seed ^ (stream * 0xd1b54a32d192ed03ull)).next();
}

struct EncoderGraph {
  ModelBuilder builder;
  uint64_t macs = 0;
  std::vector<LayerMacs> layers;
};

// The float graph with seeded He-style weights; metadata not yet filled in.
EncoderGraph build_encoder_graph(const ReferenceEncoderOptions& options);
// Name, input spec, embedding, random heads and provenance.
void fill_encoder_metadata(MetadataSpec& metadata, const ReferenceEncoderOptions& options);

}  // namespace tlvlink::quantize::encoder_internal
