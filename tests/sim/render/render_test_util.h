#pragma once
// Helpers shared by the renderer tests: renderers for the built-in profiles, common scenes and
// frame statistics.

#include <cmath>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/sim/renderer.h"

namespace tlvlink::sim::testing {

inline std::unique_ptr<Renderer> make_renderer(std::string_view profile_name, uint64_t seed = 1) {
  auto profile = sensor_profile(profile_name);
  EXPECT_TRUE(profile.ok()) << profile.error().message();
  if (!profile.ok()) return nullptr;
  auto r = Renderer::create(profile.value(), seed);
  EXPECT_TRUE(r.ok()) << r.error().message();
  return r.ok() ? std::move(r.value()) : nullptr;
}

inline ContactScene sphere(double force_n, double radius_mm = 5.0) {
  ContactScene s;
  s.geometry.shape = Shape::kSphere;
  s.geometry.radius_mm = radius_mm;
  s.loading.force_n = force_n;
  return s;
}

inline RenderOptions quiet() {  // no camera noise: differences are the physics alone
  RenderOptions o;
  o.noise_sigma_dn = 0;
  return o;
}

inline Frame render_ok(Renderer& r, const ContactScene& s, const RenderOptions& o,
                       uint64_t seed = 1) {
  Frame f;
  const Status st = r.render(s, o, seed, f);
  EXPECT_TRUE(st.ok()) << st.error().message();
  return f;
}

// Mean and standard deviation of (frame - reference) over all channels.
struct DiffStats {
  double mean = 0, stddev = 0;
};

inline DiffStats diff_stats(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double sum = 0, sum_sq = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double d = static_cast<double>(a[i]) - static_cast<double>(b[i]);
    sum += d;
    sum_sq += d * d;
  }
  const double n = static_cast<double>(a.size());
  const double mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, sum_sq / n - mean * mean))};
}

// Sum of squared second differences (a high-pass energy) of one channel over a rectangle.
inline double high_frequency_energy(const Frame& f, int c, int x0, int y0, int x1, int y1) {
  double e = 0;
  auto at = [&](int x, int y) {
    return static_cast<double>(
        f.rgb[(static_cast<size_t>(y) * static_cast<size_t>(f.width) + static_cast<size_t>(x)) * 3 +
              static_cast<size_t>(c)]);
  };
  for (int y = y0 + 1; y < y1 - 1; ++y) {
    for (int x = x0 + 1; x < x1 - 1; ++x) {
      const double lap = 4 * at(x, y) - at(x - 1, y) - at(x + 1, y) - at(x, y - 1) - at(x, y + 1);
      e += lap * lap;
    }
  }
  return e;
}

inline bool finite_state(const ContactState& s) {
  for (double v : {s.force_n, s.press_mm, s.max_gel_indentation_mm, s.kappa, s.contact_area_mm2,
                   s.contact_radius_mm, s.stick_radius_mm, s.slip_ratio, s.mean_shear_mm}) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

}  // namespace tlvlink::sim::testing
