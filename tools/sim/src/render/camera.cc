#include "render/camera.h"

#include <algorithm>

#include "render/rng.h"

namespace tlvlink::sim::internal {
namespace {

inline uint8_t to_u8(float v) {
  v = v > 0.0f ? v : 0.0f;  // also NaN -> 0
  v = v < 255.0f ? v : 255.0f;
  return static_cast<uint8_t>(static_cast<int32_t>(v + 0.5f));
}

// n unit-normal samples, five 12-bit table indices per 64-bit draw.
void fill_noise(Xoshiro256& rng, float* out, size_t n) {
  const float* table = normal_table();
  constexpr uint64_t kMask = (uint64_t{1} << kNormalTableBits) - 1;
  constexpr int kBits = kNormalTableBits;
  size_t i = 0;
  for (; i + 5 <= n; i += 5) {
    const uint64_t b = rng.next();
    out[i] = table[b & kMask];
    out[i + 1] = table[(b >> kBits) & kMask];
    out[i + 2] = table[(b >> (2 * kBits)) & kMask];
    out[i + 3] = table[(b >> (3 * kBits)) & kMask];
    out[i + 4] = table[(b >> (4 * kBits)) & kMask];
  }
  for (uint64_t b = rng.next(); i < n; ++i, b >>= kBits) out[i] = table[b & kMask];
}

[[gnu::noinline]] void scaled(float* __restrict out, const float* __restrict in, float k,
                              int32_t n) {
  for (int32_t i = 0; i < n; ++i) out[i] = k * in[i];
}

[[gnu::noinline]] void add_weighted(float* __restrict out, const float* __restrict a,
                                    const float* __restrict b, float k, int32_t n) {
  for (int32_t i = 0; i < n; ++i) out[i] += k * a[i] * b[i];
}

// Planar float rows + noise -> uint8 (vectorised), then a byte interleave.
[[gnu::noinline]] void to_u8_row(const float* __restrict r, const float* __restrict noise,
                                 float sigma, int32_t w, uint8_t* __restrict o) {
  for (int32_t x = 0; x < w; ++x) o[x] = to_u8(r[x] + sigma * noise[x]);
}

[[gnu::noinline]] void interleave3(const uint8_t* __restrict a, const uint8_t* __restrict b,
                                   const uint8_t* __restrict c, int32_t w, uint8_t* __restrict o) {
  for (int32_t x = 0; x < w; ++x) {
    o[3 * x] = a[x];
    o[3 * x + 1] = b[x];
    o[3 * x + 2] = c[x];
  }
}

}  // namespace

void compose_frame(const SensorTables& t, const std::array<const float*, 3>& delta, Roi dirty,
                   const ComposeParams& p, float* scratch, uint8_t* out) {
  const int32_t w = t.grid.width, h = t.grid.height;
  const auto led = static_cast<float>(p.led_gain);
  const auto sigma = static_cast<float>(p.noise_sigma_dn);
  Xoshiro256 rng(p.noise_seed);
  const size_t wn = static_cast<size_t>(w) * 3;
  std::array<float*, 3> planar = {scratch, scratch + w, scratch + 2 * w};
  float* noise = scratch + wn;  // planar too: the order of the draws is ours to choose
  // uint8 planar rows live after the float rows (6 * w floats hold 3 * w bytes easily).
  auto* byte_rows = reinterpret_cast<uint8_t*>(scratch + 2 * wn);
  std::array<uint8_t*, 3> bytes = {byte_rows, byte_rows + w, byte_rows + 2 * w};
  if (!(sigma > 0)) std::fill(noise, noise + wn, 0.0f);
  for (int32_t y = 0; y < h; ++y) {
    const size_t base = static_cast<size_t>(y) * static_cast<size_t>(w);
    // Background, then the (blurred) contact and marker changes where there are any.
    for (size_t c = 0; c < 3; ++c) {
      scaled(planar[c], t.background_final[c].data() + base, led, w);
    }
    if (y >= dirty.y0 && y < dirty.y1) {
      const float* vig = t.vignetting.data() + base;
      for (size_t c = 0; c < 3; ++c) {
        add_weighted(planar[c] + dirty.x0, vig + dirty.x0, delta[c] + base + dirty.x0,
                     led * t.gain[c], dirty.width());
      }
    }
    if (sigma > 0) fill_noise(rng, noise, wn);
    for (size_t c = 0; c < 3; ++c)
      to_u8_row(planar[c], noise + c * static_cast<size_t>(w), sigma, w, bytes[c]);
    interleave3(bytes[0], bytes[1], bytes[2], w, out + base * 3);
  }
}

}  // namespace tlvlink::sim::internal
