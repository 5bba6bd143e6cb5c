// The patterns: small procedural recipes (value noise, fractal noise, cellular noise and
// periodic layouts). Frequencies are in cycles per image side at zoom 1, picked by eye so
// that a 240x320 image shows a recognisable surface.

#include "gen/vision_patterns.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gen/vision_noise.h"

namespace tlvlink::sim::internal {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

struct Named {
  std::string_view name;
  Pattern pattern;
};
constexpr Named kNames[] = {
    {"plain", Pattern::kPlain},   {"glossy", Pattern::kGlossy},   {"speckle", Pattern::kSpeckle},
    {"grain", Pattern::kGrain},   {"brushed", Pattern::kBrushed}, {"bricks", Pattern::kBricks},
    {"tiles", Pattern::kTiles},   {"pores", Pattern::kPores},     {"weave", Pattern::kWeave},
    {"fibres", Pattern::kFibres}, {"bark", Pattern::kBark},       {"blades", Pattern::kBlades},
    {"clumps", Pattern::kClumps}, {"mottled", Pattern::kMottled}, {"cells", Pattern::kCells},
    {"veins", Pattern::kVeins},   {"patches", Pattern::kPatches},
};

double frac(double x) { return x - std::floor(x); }

Texel speckle(double u, double v, uint64_t s) {
  const double base = fbm(u * 6, v * 6, s, 3);
  const double dots = value_noise(u * 70, v * 70, s + 1);
  const double light = value_noise(u * 90, v * 90, s + 2);
  double shade = 0.8 + 0.3 * base;
  if (dots > 0.78) shade -= 1.6 * (dots - 0.78);
  if (light > 0.85) shade += 1.2 * (light - 0.85);
  return {shade, 0};
}

Texel grain(double u, double v, uint64_t s) {
  // Growth lines along u, bent around knots by low-frequency noise.
  const double g = v * 14 + 3.0 * fbm(u * 1.2, v * 2.5, s, 3);
  const double line = std::pow(0.5 + 0.5 * std::sin(kTwoPi * g), 6);
  const double fine = value_noise(u * 12, v * 120, s + 1);
  return {0.95 - 0.35 * line + 0.12 * (fine - 0.5), line * 0.5};
}

Texel brushed(double u, double v, uint64_t s) {
  const double streak = value_noise(u * 3, v * 180, s);
  const double band = std::exp(-std::pow(v - 0.15 * std::sin(u), 2) / 0.08);
  return {0.82 + 0.22 * streak + 0.25 * band, 0};
}

Texel bricks(double u, double v, uint64_t s) {
  constexpr double kW = 0.55, kH = 0.2, kMortar = 0.025;
  const double row = std::floor(v / kH);
  const double offset = std::fmod(std::fabs(row), 2.0) * kW * 0.5;
  const double col = std::floor((u + offset) / kW);
  const double fx = (u + offset) / kW - col, fy = v / kH - row;
  const bool mortar = fx * kW < kMortar || fy * kH < kMortar;
  const uint64_t id = mix64(static_cast<uint64_t>(static_cast<int64_t>(row)) * 31 +
                            static_cast<uint64_t>(static_cast<int64_t>(col)));
  const double rough = fbm(u * 25, v * 25, s, 2);
  if (mortar) return {0.85 + 0.2 * rough, 1};
  return {0.75 + 0.3 * unit_hash(id, s) + 0.2 * (rough - 0.5), 0};
}

Texel tiles(double u, double v, uint64_t s) {
  constexpr double kSize = 0.45, kGrout = 0.018;
  const double fx = frac(u / kSize), fy = frac(v / kSize);
  if (fx * kSize < kGrout || fy * kSize < kGrout) return {0.9, 1};
  const uint64_t id =
      mix64(static_cast<uint64_t>(static_cast<int64_t>(std::floor(u / kSize))) * 131 +
            static_cast<uint64_t>(static_cast<int64_t>(std::floor(v / kSize))));
  return {0.93 + 0.08 * unit_hash(id, s) + 0.05 * fbm(u * 8, v * 8, s, 2), 0};
}

Texel pores(double u, double v, uint64_t s) {
  const Cell c = worley(u * 14, v * 14, s);
  const double crease = std::clamp((c.d2 - c.d1) / 0.12, 0.0, 1.0);
  const double pore = value_noise(u * 110, v * 110, s + 1);
  double shade = 0.65 + 0.3 * crease + 0.1 * fbm(u * 3, v * 3, s + 2, 2);
  if (pore > 0.82) shade -= 0.25;
  return {shade, 0};
}

Texel weave(double u, double v, uint64_t s) {
  constexpr double kThreads = 45;
  const double x = u * kThreads, y = v * kThreads;
  const bool over =
      (static_cast<int64_t>(std::floor(x)) + static_cast<int64_t>(std::floor(y))) % 2 == 0;
  const double across = over ? frac(y) : frac(x);
  const double shade =
      0.6 + 0.4 * std::sin(std::numbers::pi * across) + 0.1 * (fbm(u * 4, v * 4, s, 2) - 0.5);
  return {shade, over ? 0.0 : 0.35};
}

Texel fibres(double u, double v, uint64_t s) {
  const double cloud = fbm(u * 10, v * 10, s, 3);
  const double fibre = value_noise(u * 220, v * 35, s + 1);
  return {0.92 + 0.06 * cloud + 0.06 * (fibre - 0.5), 0};
}

Texel bark(double u, double v, uint64_t s) {
  const double x = u * 9 + 1.2 * fbm(u * 2, v * 1.5, s, 3);
  const double ridge = std::fabs(std::sin(std::numbers::pi * x));
  double shade = 0.45 + 0.55 * std::sqrt(ridge) + 0.15 * (fbm(u * 25, v * 6, s + 1, 2) - 0.5);
  if (ridge < 0.12) shade *= 0.5;  // fissures
  return {shade, 0.3 * fbm(u * 3, v * 3, s + 2, 2)};
}

Texel blades(double u, double v, uint64_t s) {
  const double x = u * 32 + 6.0 * fbm(u * 1.5, v * 0.6, s, 3);
  const auto id = static_cast<uint64_t>(static_cast<int64_t>(std::floor(x)));
  const double across = std::sin(std::numbers::pi * frac(x));
  const double depth = 0.55 + 0.45 * fbm(u * 4, v * 4, s + 1, 2);
  return {(0.45 + 0.6 * across) * depth * (0.8 + 0.4 * unit_hash(id, s)),
          0.5 * unit_hash(id, s + 3)};
}

Texel clumps(double u, double v, uint64_t s) {
  const double earth = fbm(u * 8, v * 8, s, 5);
  const Cell stone = worley(u * 16, v * 16, s + 1);
  if (stone.d1 < 0.22 && unit_hash(stone.id, s) < 0.25) return {0.9 + 0.4 * (0.22 - stone.d1), 1};
  return {0.55 + 0.7 * earth, 0};
}

Texel mottled(double u, double v, uint64_t s) {
  const double q = fbm(u * 3, v * 3, s, 3);
  const double m = fbm(u * 4 + 2 * q, v * 4 - 2 * q, s + 1, 5);
  const double speck = value_noise(u * 80, v * 80, s + 2);
  return {0.7 + 0.45 * m + (speck > 0.88 ? 0.2 : 0.0), std::clamp((m - 0.45) * 3.0, 0.0, 1.0)};
}

Texel cells(double u, double v, uint64_t s) {
  const Cell c = worley(u * 9, v * 9, s);
  if (c.d2 - c.d1 < 0.08) return {0.35, 0};  // gaps between pebbles
  const double rounded = 1.0 - 0.6 * c.d1;   // pebbles are brighter at the top
  return {(0.65 + 0.45 * unit_hash(c.id, s)) * rounded + 0.1 * fbm(u * 40, v * 40, s, 2),
          unit_hash(c.id, s + 1)};
}

Texel veins(double u, double v, uint64_t s) {
  const double off = std::fabs(v - 0.1 * std::sin(u * 2));
  const double side = frac((u + 1.4 * off) * 6);
  double mix = 0;
  if (off < 0.012)
    mix = 1;
  else if (std::fabs(side - 0.5) < 0.025)
    mix = 0.6;
  return {0.85 + 0.2 * fbm(u * 6, v * 6, s, 3), mix};
}

Texel patches(double u, double v, uint64_t s) {
  const Cell c = worley(u * 3, v * 3, s);
  return {0.8 + 0.3 * unit_hash(c.id, s) + 0.1 * fbm(u * 12, v * 12, s + 1, 2),
          unit_hash(c.id, s + 1) > 0.5 ? 1.0 : 0.0};
}

}  // namespace

Result<Pattern> parse_pattern(std::string_view name) {
  for (const Named& n : kNames) {
    if (n.name == name) return n.pattern;
  }
  return Error::make(ErrorCode::kInvalidArgument, "vision pattern '%.*s' is unknown",
                     static_cast<int>(name.size()), name.data());
}

Texel pattern_texel(Pattern pattern, double u, double v, uint64_t seed) {
  switch (pattern) {
    case Pattern::kPlain: return {0.9 + 0.2 * fbm(u * 3, v * 3, seed, 3), 0};
    case Pattern::kGlossy: {
      const double sheen =
          std::pow(std::max(0.0, std::sin((u + v) * 5 + 2 * fbm(u, v, seed, 2))), 12);
      return {0.85 + 0.1 * fbm(u * 2, v * 2, seed, 2) + 0.4 * sheen, 0};
    }
    case Pattern::kSpeckle: return speckle(u, v, seed);
    case Pattern::kGrain: return grain(u, v, seed);
    case Pattern::kBrushed: return brushed(u, v, seed);
    case Pattern::kBricks: return bricks(u, v, seed);
    case Pattern::kTiles: return tiles(u, v, seed);
    case Pattern::kPores: return pores(u, v, seed);
    case Pattern::kWeave: return weave(u, v, seed);
    case Pattern::kFibres: return fibres(u, v, seed);
    case Pattern::kBark: return bark(u, v, seed);
    case Pattern::kBlades: return blades(u, v, seed);
    case Pattern::kClumps: return clumps(u, v, seed);
    case Pattern::kMottled: return mottled(u, v, seed);
    case Pattern::kCells: return cells(u, v, seed);
    case Pattern::kVeins: return veins(u, v, seed);
    case Pattern::kPatches: return patches(u, v, seed);
  }
  return {};
}

std::array<double, 3> secondary_colour(Pattern pattern, const std::array<uint8_t, 3>& base,
                                       uint64_t seed) {
  const std::array<double, 3> b = {static_cast<double>(base[0]), static_cast<double>(base[1]),
                                   static_cast<double>(base[2])};
  switch (pattern) {
    case Pattern::kBricks: return {195, 190, 180};  // mortar
    case Pattern::kTiles: return {225, 225, 218};   // grout
    case Pattern::kClumps: return {150, 145, 135};  // stones in the earth
    case Pattern::kBlades: return {b[0] * 1.6 + 40, b[1] * 1.1 + 20, b[2] * 0.8};  // dry blades
    case Pattern::kVeins: return {b[0] * 1.5 + 30, b[1] * 1.3 + 30, b[2] * 1.2 + 20};
    case Pattern::kGrain:
    case Pattern::kBark:
    case Pattern::kMottled: return {b[0] * 0.6, b[1] * 0.6, b[2] * 0.6};
    case Pattern::kWeave: return {b[0] * 0.7 + 20, b[1] * 0.7 + 10, b[2] * 0.7};
    case Pattern::kCells: return {b[0] * 0.9 + 25, b[1] * 0.85 + 15, b[2] * 0.8};
    case Pattern::kPatches: {
      // Another colour of the same brightness: rotate the channels.
      const size_t r = 1 + static_cast<size_t>(mix64(seed) % 2);
      return {b[r % 3], b[(r + 1) % 3], b[(r + 2) % 3]};
    }
    default: return b;
  }
}

}  // namespace tlvlink::sim::internal
