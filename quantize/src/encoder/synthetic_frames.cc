// Synthetic tactile frames for calibration, golden pairs and tests. Plain arithmetic only
// (no exp/sin), so the same seed gives the same bytes on every platform.

#include <algorithm>
#include <cmath>

#include "encoder/encoder_internal.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink::quantize {

using encoder_internal::Rng;

namespace {
constexpr int kMaxBlobs = 6;
constexpr float kNoiseLevels = 4.0f;  // sensor noise, in 8-bit levels (std of the approximation)
}  // namespace

std::vector<uint8_t> synthetic_touch_frame(int32_t height, int32_t width, uint64_t seed) {
  Rng rng(encoder_internal::derive_seed(seed, 3));
  // Illumination: a base colour plus a linear gradient per channel (LED falloff).
  float base[3], gx[3], gy[3];
  for (int c = 0; c < 3; ++c) {
    base[c] = rng.uniform(60.0f, 190.0f);
    gx[c] = rng.uniform(-60.0f, 60.0f);
    gy[c] = rng.uniform(-60.0f, 60.0f);
  }
  // Contact blobs: a smooth bump (1 - r^2/s^2)^2 with a per-channel signed amplitude, the way
  // a pressed gel shifts colour under coloured lights.
  struct Blob {
    float cx, cy, s, amp[3];
  };
  const int blobs = 1 + static_cast<int>(rng.uniform() * kMaxBlobs);
  std::vector<Blob> list(static_cast<size_t>(blobs));
  for (Blob& b : list) {
    b.cx = rng.uniform(0.0f, 1.0f);
    b.cy = rng.uniform(0.0f, 1.0f);
    b.s = rng.uniform(0.05f, 0.35f);
    for (float& a : b.amp) a = rng.uniform(-90.0f, 90.0f);
  }
  std::vector<uint8_t> px(static_cast<size_t>(height) * width * 3);
  size_t i = 0;
  for (int32_t y = 0; y < height; ++y) {
    const float v = (static_cast<float>(y) + 0.5f) / static_cast<float>(height);
    for (int32_t x = 0; x < width; ++x) {
      const float u = (static_cast<float>(x) + 0.5f) / static_cast<float>(width);
      float value[3];
      for (int c = 0; c < 3; ++c) value[c] = base[c] + gx[c] * (u - 0.5f) + gy[c] * (v - 0.5f);
      for (const Blob& b : list) {
        const float r2 = ((u - b.cx) * (u - b.cx) + (v - b.cy) * (v - b.cy)) / (b.s * b.s);
        if (r2 >= 1.0f) continue;
        const float bump = (1.0f - r2) * (1.0f - r2);
        for (int c = 0; c < 3; ++c) value[c] += b.amp[c] * bump;
      }
      for (int c = 0; c < 3; ++c) {
        const float noisy = value[c] + kNoiseLevels * rng.normal();
        px[i++] = static_cast<uint8_t>(std::clamp(std::floor(noisy + 0.5f), 0.0f, 255.0f));
      }
    }
  }
  return px;
}

}  // namespace tlvlink::quantize
