// Sensor-variation augmentation: per-channel gain, exposure, camera noise.

#include "augment.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "augment_rng.h"

namespace tlvlink::trainer {
using rng::normal;
using rng::splitmix;

uint64_t augment_seed(uint64_t run_seed, int64_t step, int64_t index) {
  uint64_t s = run_seed ^ 0x5851f42d4c957f2dull;
  s ^= splitmix(s) + static_cast<uint64_t>(step) * 0x9e3779b97f4a7c15ull;
  s ^= splitmix(s) + static_cast<uint64_t>(index) * 0xd1b54a32d192ed03ull;
  return splitmix(s);
}

void augment_frame(const uint8_t* src, uint8_t* dst, int32_t height, int32_t width,
                   const AugmentOptions& o, uint64_t seed) {
  const size_t pixels = static_cast<size_t>(height) * static_cast<size_t>(width);
  if (!o.enabled()) {
    std::memcpy(dst, src, pixels * 3);
    return;
  }
  uint64_t state = seed;
  double mean[3] = {0, 0, 0};
  for (size_t p = 0; p < pixels; ++p)
    for (size_t c = 0; c < 3; ++c) mean[c] += src[p * 3 + c];
  const double exposure = std::exp(o.exposure_sigma * normal(state));
  float gain[3], offset[3];
  for (size_t c = 0; c < 3; ++c) {
    mean[c] /= static_cast<double>(std::max<size_t>(pixels, 1));
    // v' = exposure * (mean + g (v - mean)): the channel's contrast scales by its LED gain
    // around its level, the whole frame by the exposure.
    const double g = std::exp(o.gain_sigma * normal(state));
    gain[c] = static_cast<float>(exposure * g);
    offset[c] = static_cast<float>(exposure * mean[c] * (1 - g));
  }
  for (size_t p = 0; p < pixels; ++p) {
    for (size_t c = 0; c < 3; ++c) {
      float v = gain[c] * static_cast<float>(src[p * 3 + c]) + offset[c];
      if (o.noise_dn > 0) v += static_cast<float>(o.noise_dn * normal(state));
      dst[p * 3 + c] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 255.0f)));
    }
  }
}

}  // namespace tlvlink::trainer
