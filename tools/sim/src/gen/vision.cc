// The vision image: pattern(object coordinates) x object colour x lighting x vignetting + noise.

#include "tlvlink/sim/vision.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "gen/rng.h"
#include "gen/vision_patterns.h"

namespace tlvlink::sim {
namespace {

constexpr int32_t kMaxSide = 8192;
constexpr double kVignetting = 0.15;  // corner darkening of a cheap camera lens
constexpr int32_t kStep = 2;          // pattern lattice spacing (px)
// Only large images use the lattice: the finest patterns (weave, speckle) have ~50-100 cycles per
// side and would alias on it below ~400 px.
constexpr int32_t kMinSideForLattice = 400;

Status check(const char* field, double value, double lo, double hi) {
  TLV_ENSURE(std::isfinite(value) && value >= lo && value <= hi, ErrorCode::kInvalidArgument,
             "vision view: %s = %g is outside [%g, %g]", field, value, lo, hi);
  return {};
}

Status validate(const VisionView& v) {
  TLV_TRY(check("shift_x", v.shift_x, -10, 10));
  TLV_TRY(check("shift_y", v.shift_y, -10, 10));
  TLV_TRY(check("zoom", v.zoom, 0.25, 4));
  TLV_TRY(check("rotation_deg", v.rotation_deg, -360, 360));
  TLV_TRY(check("light_angle_deg", v.light_angle_deg, -360, 360));
  TLV_TRY(check("light_strength", v.light_strength, 0, 0.8));
  TLV_TRY(check("brightness", v.brightness, 0.3, 2));
  TLV_TRY(check("noise_sigma_dn", v.noise_sigma_dn, 0, 20));
  return {};
}

}  // namespace

VisionView random_vision_view(uint64_t seed) {
  internal::Rng rng(internal::derive_seed(seed, {internal::tag(internal::Stream::kVision)}));
  VisionView v;
  v.shift_x = rng.uniform(-0.5, 0.5);
  v.shift_y = rng.uniform(-0.5, 0.5);
  v.zoom = rng.log_uniform(0.8, 1.25);
  v.rotation_deg = rng.uniform(-15, 15);
  v.light_angle_deg = rng.uniform(0, 360);
  v.light_strength = rng.uniform(0.05, 0.35);
  v.brightness = rng.uniform(0.85, 1.15);
  v.noise_sigma_dn = rng.uniform(1, 4);
  return v;
}

Status render_vision_image(const MaterialSample& material, uint64_t appearance_seed,
                           const VisionView& view, uint64_t noise_seed, int32_t height,
                           int32_t width, RgbImage& out) {
  TLV_ENSURE(height >= 1 && height <= kMaxSide && width >= 1 && width <= kMaxSide,
             ErrorCode::kInvalidArgument, "vision image: size %dx%d is outside 1..%d", height,
             width, kMaxSide);
  TLV_TRY(validate(view));
  TLV_ASSIGN_OR_RETURN(const MaterialClass* cls, material_class(material.class_id));
  TLV_ASSIGN_OR_RETURN(const internal::Pattern pattern, internal::parse_pattern(cls->pattern));

  const uint64_t layout =
      internal::derive_seed(appearance_seed, {internal::tag(internal::Stream::kTexture)});
  const std::array<double, 3> base = {static_cast<double>(material.colour[0]),
                                      static_cast<double>(material.colour[1]),
                                      static_cast<double>(material.colour[2])};
  const std::array<double, 3> second = internal::secondary_colour(pattern, material.colour, layout);
  const double side = static_cast<double>(std::min(height, width));
  const double rot = view.rotation_deg * std::numbers::pi / 180.0;
  const double cr = std::cos(rot) / view.zoom, sr = std::sin(rot) / view.zoom;
  const double la = view.light_angle_deg * std::numbers::pi / 180.0;
  const double lx = std::cos(la), ly = std::sin(la);
  internal::Rng noise(
      internal::derive_seed(noise_seed, {internal::tag(internal::Stream::kVision), 1}));

  // The pattern is evaluated on a lattice of every kStep-th pixel and interpolated: a camera
  // image is soft at the pixel scale anyway, and the pattern is most of the cost.
  const int32_t step = std::min(height, width) >= kMinSideForLattice ? kStep : 1;
  const int32_t lh = (height - 1) / step + 2, lw = (width - 1) / step + 2;
  std::vector<internal::Texel> lattice(static_cast<size_t>(lh) * static_cast<size_t>(lw));
  for (int32_t j = 0; j < lh; ++j) {
    const double ny = (j * step + 0.5 - height * 0.5) / side;  // centred, 1 = shorter side
    for (int32_t i = 0; i < lw; ++i) {
      const double nx = (i * step + 0.5 - width * 0.5) / side;
      const double u = cr * nx - sr * ny + view.shift_x;
      const double v = sr * nx + cr * ny + view.shift_y;
      lattice[static_cast<size_t>(j) * static_cast<size_t>(lw) + static_cast<size_t>(i)] =
          internal::pattern_texel(pattern, u, v, layout);
    }
  }

  out.height = height;
  out.width = width;
  out.rgb.resize(static_cast<size_t>(height) * static_cast<size_t>(width) * 3);
  uint8_t* px = out.rgb.data();
  const double inv_step = 1.0 / step;
  for (int32_t y = 0; y < height; ++y) {
    const double ny = (y + 0.5 - height * 0.5) / side;
    const int32_t j = y / step;
    const double ty = (y - j * step) * inv_step;
    const internal::Texel* row0 = &lattice[static_cast<size_t>(j) * static_cast<size_t>(lw)];
    const internal::Texel* row1 = row0 + lw;
    for (int32_t x = 0; x < width; ++x) {
      const double nx = (x + 0.5 - width * 0.5) / side;
      const int32_t i = x / step;
      const double tx = (x - i * step) * inv_step;
      auto lerp2 = [&](double internal::Texel::*field) {
        const double top = row0[i].*field + (row0[i + 1].*field - row0[i].*field) * tx;
        const double bottom = row1[i].*field + (row1[i + 1].*field - row1[i].*field) * tx;
        return top + (bottom - top) * ty;
      };
      const double shade = lerp2(&internal::Texel::shade);
      const double mix = std::clamp(lerp2(&internal::Texel::mix), 0.0, 1.0);
      const double r2 = (nx * nx + ny * ny) / 0.6;  // ~1 at a 4:3 corner
      const double light = view.brightness * (1.0 + view.light_strength * (lx * nx + ly * ny)) *
                           (1.0 - kVignetting * r2);
      for (size_t c = 0; c < 3; ++c) {
        const double colour = base[c] + (second[c] - base[c]) * mix;
        const double value = colour * shade * light + view.noise_sigma_dn * noise.fast_normal();
        *px++ = static_cast<uint8_t>(std::clamp(value, 0.0, 255.0) + 0.5);
      }
    }
  }
  return {};
}

}  // namespace tlvlink::sim
