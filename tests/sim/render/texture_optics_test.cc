// Texture (roughness shows as high-frequency content, seeded), the shading gain calibration, and
// the renderer's numerical building blocks (recursive Gaussian, noise table).
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/blur.h"
#include "render/model_constants.h"
#include "render/rng.h"
#include "render/sensor_tables.h"
#include "render/shading.h"
#include "render/texture.h"
#include "sim/render/render_test_util.h"

namespace tlvlink::sim {
namespace {

using testing::make_renderer;
using testing::quiet;
using testing::render_ok;
using testing::sphere;

constexpr double kPi = 3.14159265358979323846;

TEST(SimRenderTexture, RoughSurfacesHaveMoreHighFrequencyEnergy) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  ContactScene smooth = sphere(8, 10);
  smooth.texture = {0.5, 0.3, 0.8, 4};
  ContactScene rough = smooth;
  rough.texture.sq_um = 40;
  const Frame fs = render_ok(*r, smooth, quiet());
  const Frame fr = render_ok(*r, rough, quiet());
  // Inside the contact (radius > 2 mm = 31 px): a 40 x 40 px window at the centre.
  double es = 0, er = 0;
  for (int c = 0; c < 3; ++c) {
    es += testing::high_frequency_energy(fs, c, 140, 100, 180, 140);
    er += testing::high_frequency_energy(fr, c, 140, 100, 180, 140);
  }
  EXPECT_GT(er, 10 * es) << "smooth " << es << " rough " << er;
}

TEST(SimRenderTexture, IsFixedByItsSeed) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  ContactScene a = sphere(8, 10);
  a.texture = {30, 0.3, 0.8, 4};
  ContactScene b = a;
  b.texture.seed = 5;
  EXPECT_EQ(render_ok(*r, a, quiet()).rgb, render_ok(*r, a, quiet()).rgb);
  EXPECT_NE(render_ok(*r, a, quiet()).rgb, render_ok(*r, b, quiet()).rgb);
}

TEST(SimRenderTexture, HasTheRequestedRmsAndZeroMean) {
  const internal::FrameGrid grid{240, 320, 0.0634};
  internal::FractalTexture tex(grid);
  std::vector<float> h(grid.pixels(), 0.0f);
  const internal::Roi roi{20, 10, 300, 230};
  for (double hurst : {0.0, 0.5, 1.0}) {
    SCOPED_TRACE(hurst);
    std::fill(h.begin(), h.end(), 0.0f);
    tex.add({25, 0.4, hurst, 9}, 0.3, -0.2, roi, h.data());
    double sum = 0, sum_sq = 0, outside = 0;
    for (int32_t y = 0; y < grid.height; ++y) {
      for (int32_t x = 0; x < grid.width; ++x) {
        const auto v = static_cast<double>(h[static_cast<size_t>(y * grid.width + x)]);
        const bool in = x >= roi.x0 && x < roi.x1 && y >= roi.y0 && y < roi.y1;
        if (in) {
          sum += v;
          sum_sq += v * v;
        } else {
          outside += std::fabs(v);
        }
      }
    }
    const double n = static_cast<double>(roi.width() * roi.height());
    constexpr double kRelTolerance = 1e-3;  // float accumulation over 60k pixels
    EXPECT_NEAR(std::sqrt(sum_sq / n), 25e-3, kRelTolerance * 25e-3);
    EXPECT_NEAR(sum / n, 0.0, kRelTolerance * 25e-3);
    EXPECT_EQ(outside, 0.0);
  }
}

TEST(SimRenderShading, GainMatchesTaximMagnitudes) {
  // 1-3 DN per degree at small slopes, |delta| <= ~80 DN at 45 deg, for every profile (before
  // the per-sensor +-15 % LED spread).
  for (std::string_view name : sensor_profile_names()) {
    SCOPED_TRACE(std::string(name));
    auto p = sensor_profile(name);
    ASSERT_TRUE(p.ok());
    std::array<internal::LightModel, 4> lights{};
    float scale = 0;
    internal::build_lights(p.value(), lights, scale);
    ASSERT_GT(scale, 0.0f);
    double gain = 0, at45 = 0;
    for (int k = 0; k < 360; k += 5) {
      const double phi = k * kPi / 180;
      const auto c = static_cast<float>(std::cos(phi)), s = static_cast<float>(std::sin(phi));
      const float one_deg = std::tan(static_cast<float>(kPi / 180));
      const auto d1 =
          internal::shading_delta(lights.data(), p->light_count, one_deg * c, one_deg * s, 0, 0);
      const auto d45 = internal::shading_delta(lights.data(), p->light_count, c, s, 0, 0);
      for (int ch = 0; ch < 3; ++ch) {
        gain = std::max(gain, static_cast<double>(std::fabs(d1[static_cast<size_t>(ch)])));
        at45 = std::max(at45, static_cast<double>(std::fabs(d45[static_cast<size_t>(ch)])));
      }
    }
    EXPECT_GE(gain, 1.0);
    EXPECT_LE(gain, 3.0);
    EXPECT_NEAR(at45, internal::kMaxDeltaAt45Dn, 1.0);  // sampled every 5 deg vs every 1 deg
  }
}

TEST(SimRenderBlur, RecursiveGaussianMatchesTheAnalyticKernel) {
  constexpr int kSize = 121;
  internal::GaussianBlur blur(kSize, kSize);
  for (double sigma : {2.5, 6.0, 14.0}) {
    SCOPED_TRACE(sigma);
    std::vector<float> p(kSize * kSize, 0.0f);
    p[(kSize / 2) * kSize + kSize / 2] = 1.0f;
    internal::EdgeModes zeros;  // the impulse response lies inside the plane
    zeros.left = zeros.right = zeros.top = zeros.bottom = internal::EdgeMode::kZero;
    blur.blur({p.data(), kSize, kSize, kSize}, sigma, zeros);
    double sum = 0, max_err = 0;
    const double peak = 1.0 / (2 * kPi * sigma * sigma);
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        const double dx = x - kSize / 2, dy = y - kSize / 2;
        const double g = peak * std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma));
        const auto v = static_cast<double>(p[static_cast<size_t>(y * kSize + x)]);
        sum += v;
        max_err = std::max(max_err, std::fabs(v - g));
      }
    }
    // Deriche's filter is within ~0.05 % of the peak per axis; the plane (+-4.3 sigma at the
    // largest sigma) loses < 1e-4 of the mass.
    constexpr double kShapeTolerance = 0.003, kMassTolerance = 1e-3;
    EXPECT_LT(max_err, kShapeTolerance * peak);
    EXPECT_NEAR(sum, 1.0, kMassTolerance);
  }
}

TEST(SimRenderBlur, ReplicateEdgesKeepAConstantField) {
  internal::GaussianBlur blur(64, 48);
  for (double sigma : {0.7, 1.5, 3.0, 9.0}) {
    SCOPED_TRACE(sigma);
    std::vector<float> p(64 * 48, 2.5f);
    blur.blur({p.data(), 64, 48, 64}, sigma, internal::EdgeModes{});
    for (float v : p) ASSERT_NEAR(v, 2.5f, 2.5f * 1e-4f);  // float rounding of 8-tap sums
  }
}

TEST(SimRenderNoise, TableHasUnitVariance) {
  const float* t = internal::normal_table();
  double sum = 0, sum_sq = 0;
  constexpr int kN = 1 << internal::kNormalTableBits;
  for (int i = 0; i < kN; ++i) {
    sum += static_cast<double>(t[i]);
    sum_sq += static_cast<double>(t[i]) * static_cast<double>(t[i]);
  }
  EXPECT_NEAR(sum / kN, 0.0, 1e-6);
  EXPECT_NEAR(sum_sq / kN, 1.0, 1e-5);
}

}  // namespace
}  // namespace tlvlink::sim
