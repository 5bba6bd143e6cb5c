#include "render/sensor_tables.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "render/model_constants.h"
#include "render/rng.h"

namespace tlvlink::sim::internal {
namespace {

// Low-order illumination polynomial of channel c at normalised position (u, v) in [-1, 1]^2:
// random quadratic terms plus a gradient toward each light of that colour (the LED side of the
// gel is brighter). a[0..1] already include the light gradient.
double illumination_poly(const std::array<double, 5>& a, double u, double v) {
  return a[0] * u + a[1] * v + a[2] * u * u + a[3] * u * v + a[4] * v * v;
}

}  // namespace

void build_lights(const SensorProfile& profile, std::array<LightModel, 4>& lights, float& scale) {
  for (int i = 0; i < profile.light_count; ++i) {
    const Light& l = profile.lights[static_cast<size_t>(i)];
    const double az = l.azimuth_deg * std::numbers::pi / 180;
    const double norm = std::sqrt(1 + profile.light_elevation * profile.light_elevation);
    LightModel& m = lights[static_cast<size_t>(i)];
    m.lx = static_cast<float>(std::cos(az) / norm);
    m.ly = static_cast<float>(std::sin(az) / norm);
    m.lz = static_cast<float>(profile.light_elevation / norm);
    const float lz2 = m.lz * m.lz;
    m.spec0 = lz2 * lz2 * m.lz;
    for (int c = 0; c < 3; ++c) {
      m.amp[static_cast<size_t>(c)] = static_cast<float>(l.rgb[static_cast<size_t>(c)]);
    }
  }
  // Strongest |delta| over tilt directions at 45 deg (slope 1) with unit amplitudes.
  float worst = 0;
  for (int k = 0; k < 360; ++k) {
    const double phi = k * std::numbers::pi / 180;
    const auto d =
        shading_delta(lights.data(), profile.light_count, static_cast<float>(std::cos(phi)),
                      static_cast<float>(std::sin(phi)), 0.0f, 0.0f);
    for (float v : d) worst = std::max(worst, std::fabs(v));
  }
  scale = worst > 0 ? static_cast<float>(kMaxDeltaAt45Dn) / worst : 0.0f;
  for (int i = 0; i < profile.light_count; ++i) {
    for (float& a : lights[static_cast<size_t>(i)].amp) a *= scale;
  }
}

SensorTables build_sensor_tables(const SensorProfile& p, uint64_t sensor_seed, GaussianBlur& blur,
                                 Periphery periphery) {
  SensorTables t;
  t.grid = {p.height + 2 * periphery.y, p.width + 2 * periphery.x, p.mm_per_px};
  t.view = {periphery.x, periphery.y, periphery.x + p.width, periphery.y + p.height};
  const FrameGrid& g = t.grid;
  const size_t n = g.pixels();
  Xoshiro256 rng(mix64(sensor_seed ^ 0x5E5502ull));

  // Per-instance draws, in a fixed order.
  std::array<std::array<double, 5>, 3> poly{};
  for (auto& a : poly) {
    for (double& v : a) v = rng.uniform(-1, 1);
  }
  for (int c = 0; c < 3; ++c) {  // brighter toward each LED of this colour
    for (int i = 0; i < p.light_count; ++i) {
      const Light& l = p.lights[static_cast<size_t>(i)];
      const double az = l.azimuth_deg * std::numbers::pi / 180,
                   k = 0.5 * l.rgb[static_cast<size_t>(c)];
      poly[static_cast<size_t>(c)][0] += k * std::cos(az);
      poly[static_cast<size_t>(c)][1] += k * std::sin(az);
    }
  }
  std::array<double, 4> light_gain{};
  for (double& v : light_gain) v = rng.uniform(1 - kPerLightGainSpread, 1 + kPerLightGainSpread);
  std::array<double, 3> white_balance{};
  for (double& v : white_balance) v = rng.uniform(1 - kWhiteBalanceSpread, 1 + kWhiteBalanceSpread);
  const double exposure = rng.uniform(1 - kOverallGainSpread, 1 + kOverallGainSpread);
  for (int c = 0; c < 3; ++c) {
    t.gain[static_cast<size_t>(c)] = static_cast<float>(
        p.channel_gain[static_cast<size_t>(c)] * white_balance[static_cast<size_t>(c)] * exposure);
  }

  build_lights(p, t.lights, t.light_scale);
  t.light_count = p.light_count;
  for (int i = 0; i < p.light_count; ++i) {
    for (float& a : t.lights[static_cast<size_t>(i)].amp) {
      a *= static_cast<float>(light_gain[static_cast<size_t>(i)]);
    }
  }

  // Background: b_c + amplitude * poly / max|poly|, then vignetting. Coordinates, the maximum
  // and the corner radius are those of the processed frame (t.view), also with a periphery.
  const double half_w = 0.5 * p.width * g.mm_per_px, half_h = 0.5 * p.height * g.mm_per_px;
  const Roi& view = t.view;
  t.vignetting.resize(n);
  for (int c = 0; c < 3; ++c) {
    auto& raw = t.background_raw[static_cast<size_t>(c)];
    raw.resize(n);
    double max_abs = 0;
    for (int32_t y = 0; y < g.height; ++y) {
      for (int32_t x = 0; x < g.width; ++x) {
        const double v =
            illumination_poly(poly[static_cast<size_t>(c)], g.x_mm(x) / half_w, g.y_mm(y) / half_h);
        raw[static_cast<size_t>(y * g.width + x)] = static_cast<float>(v);
        if (y >= view.y0 && y < view.y1 && x >= view.x0 && x < view.x1)
          max_abs = std::max(max_abs, std::fabs(v));
      }
    }
    const double amp = max_abs > 0 ? p.background_nonuniformity_dn / max_abs : 0;
    const double base = p.background_rgb[static_cast<size_t>(c)];
    for (float& v : raw) v = static_cast<float>(std::max(0.0, base + amp * static_cast<double>(v)));
  }
  const double corner2 = half_w * half_w + half_h * half_h;
  for (int32_t y = 0; y < g.height; ++y) {
    for (int32_t x = 0; x < g.width; ++x) {
      const double r2 = (g.x_mm(x) * g.x_mm(x) + g.y_mm(y) * g.y_mm(y)) / corner2;
      // r > 1 only in a periphery, where a strong k_v would go negative: dark, not negative.
      t.vignetting[static_cast<size_t>(y * g.width + x)] =
          static_cast<float>(std::max(0.0, 1 - p.vignetting * r2));
    }
  }
  t.background_u8.resize(n * 3);
  for (int c = 0; c < 3; ++c) {
    auto& fin = t.background_final[static_cast<size_t>(c)];
    fin = t.background_raw[static_cast<size_t>(c)];
    blur.blur_direct({fin.data(), g.width, g.height, g.width}, kCameraBlurSigmaPx,
                     kCameraBlurRadiusPx, EdgeModes{});
    for (size_t i = 0; i < n; ++i) {
      fin[i] *= t.vignetting[i] * t.gain[static_cast<size_t>(c)];
      const float v = std::clamp(fin[i], 0.0f, 255.0f);
      t.background_u8[i * 3 + static_cast<size_t>(c)] = static_cast<uint8_t>(v + 0.5f);
    }
  }

  // Dome: paraboloid with its apex (sag) at the centre and 0 at the corners.
  if (p.dome_sag_mm > 0) {
    t.dome_height.resize(n);
    t.dome_p.resize(n);
    t.dome_q.resize(n);
    for (int32_t y = 0; y < g.height; ++y) {
      for (int32_t x = 0; x < g.width; ++x) {
        const double X = g.x_mm(x), Y = g.y_mm(y);
        const size_t i = static_cast<size_t>(y * g.width + x);
        t.dome_height[i] = static_cast<float>(p.dome_sag_mm * (1 - (X * X + Y * Y) / corner2));
        t.dome_p[i] = static_cast<float>(-2 * p.dome_sag_mm * X / corner2);
        t.dome_q[i] = static_cast<float>(-2 * p.dome_sag_mm * Y / corner2);
      }
    }
    for (int l = 0; l < t.light_count; ++l) {
      auto& rest = t.dome_rest[static_cast<size_t>(l)];
      rest.resize(n);
      for (size_t i = 0; i < n; ++i) {
        rest[i] =
            shading_term_for_slopes(t.lights[static_cast<size_t>(l)], t.dome_p[i], t.dome_q[i]);
      }
      t.dome_rest_ptr[static_cast<size_t>(l)] = rest.data();
    }
  }

  // A periphery gets the whole pitches that fit in it (the gel's grid continues under it).
  auto extra = [&](int32_t pad, int32_t count, int32_t side_px) {
    if (pad == 0) return 0;
    const double room =
        0.5 * (side_px + 2 * pad) * g.mm_per_px - 0.5 * (count - 1) * p.marker_pitch_mm;
    return std::max(0, static_cast<int32_t>(std::floor(room / p.marker_pitch_mm)));
  };
  const int32_t rows = p.marker_rows + 2 * extra(periphery.y, p.marker_rows, p.height);
  const int32_t cols = p.marker_cols + 2 * extra(periphery.x, p.marker_cols, p.width);
  t.marker_rest_mm.reserve(static_cast<size_t>(rows * cols));
  for (int32_t r = 0; r < rows; ++r) {
    for (int32_t c = 0; c < cols; ++c) {
      t.marker_rest_mm.push_back(
          {(c - 0.5 * (cols - 1)) * p.marker_pitch_mm, (r - 0.5 * (rows - 1)) * p.marker_pitch_mm});
    }
  }
  return t;
}

}  // namespace tlvlink::sim::internal
