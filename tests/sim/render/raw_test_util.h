#pragma once
// Helpers shared by the raw camera tests: cameras and decoders for the built-in profiles,
// frame-difference statistics and the centroid of a contact's change.

#include <cmath>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/sim/raw_camera.h"

namespace tlvlink::sim::testing {

inline std::unique_ptr<RawCamera> make_camera(std::string_view name, uint64_t seed = 1) {
  auto profile = sensor_profile(name);
  EXPECT_TRUE(profile.ok());
  if (!profile.ok()) return nullptr;
  auto camera = RawCamera::create(profile.value(), seed);
  EXPECT_TRUE(camera.ok()) << camera.error().message();
  return camera.ok() ? std::move(camera.value()) : nullptr;
}

inline std::unique_ptr<RawDecoder> make_decoder(std::string_view name, int32_t scale = 0) {
  auto profile = sensor_profile(name);
  EXPECT_TRUE(profile.ok());
  if (!profile.ok()) return nullptr;
  RecoverOptions o;
  o.jpeg_scale_denominator = scale;
  auto decoder = RawDecoder::create(profile.value(), o);
  EXPECT_TRUE(decoder.ok()) << decoder.error().message();
  return decoder.ok() ? std::move(decoder.value()) : nullptr;
}

inline RawFrame render_raw(RawCamera& camera, const ContactScene& scene,
                           const RenderOptions& options, uint64_t seed = 1) {
  RawFrame f;
  const Status st = camera.render(scene, options, seed, f);
  EXPECT_TRUE(st.ok()) << st.error().message();
  return f;
}

inline std::vector<uint8_t> recover_ok(RawDecoder& decoder, const std::vector<uint8_t>& raw) {
  std::vector<uint8_t> rgb;
  const Status st = decoder.recover(raw, rgb);
  EXPECT_TRUE(st.ok()) << st.error().message();
  return rgb;
}

// Mean absolute difference (DN) and PSNR (dB, peak 255) of two same-size images.
struct Closeness {
  double mean_abs = 0, psnr_db = 0;
};

inline Closeness closeness(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  EXPECT_EQ(a.size(), b.size());
  double abs_sum = 0, sq_sum = 0;
  const size_t n = std::min(a.size(), b.size());
  for (size_t i = 0; i < n; ++i) {
    const double d = static_cast<double>(a[i]) - static_cast<double>(b[i]);
    abs_sum += std::fabs(d);
    sq_sum += d * d;
  }
  const double mse = sq_sum / static_cast<double>(n);
  return {abs_sum / static_cast<double>(n), mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : 99};
}

// Centroid (x, y in pixels) of the summed |a - b| over the channels, counting only pixels whose
// change exceeds `threshold` DN (so JPEG ripple and noise do not pull it); count = such pixels.
struct Centroid {
  double x = 0, y = 0;
  int64_t count = 0;
};

inline Centroid change_centroid(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b,
                                int32_t width, int32_t height, int32_t channels, double threshold) {
  Centroid c;
  double wsum = 0;
  for (int32_t y = 0; y < height; ++y) {
    for (int32_t x = 0; x < width; ++x) {
      double d = 0;
      const size_t i =
          (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) *
          static_cast<size_t>(channels);
      for (int32_t k = 0; k < channels; ++k) {
        d += std::fabs(static_cast<double>(a[i + static_cast<size_t>(k)]) -
                       static_cast<double>(b[i + static_cast<size_t>(k)]));
      }
      if (d <= threshold) continue;
      c.x += d * x;
      c.y += d * y;
      wsum += d;
      ++c.count;
    }
  }
  if (wsum > 0) {
    c.x /= wsum;
    c.y /= wsum;
  }
  return c;
}

}  // namespace tlvlink::sim::testing
