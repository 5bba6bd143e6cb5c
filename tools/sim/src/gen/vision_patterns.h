#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "vision_patterns.h is internal to tools/sim: include its public headers instead"
#endif
// Surface patterns of the vision images, one per material appearance ("grain", "weave", ...).
// A pattern maps object coordinates to a shade (multiplies the object colour) and a mix
// towards a secondary colour (mortar, grout, veins, a second thread colour, ...).

#include <array>
#include <cstdint>
#include <string_view>

#include "tlvlink/error.h"

namespace tlvlink::sim::internal {

enum class Pattern : uint8_t {
  kPlain,
  kGlossy,
  kSpeckle,
  kGrain,
  kBrushed,
  kBricks,
  kTiles,
  kPores,
  kWeave,
  kFibres,
  kBark,
  kBlades,
  kClumps,
  kMottled,
  kCells,
  kVeins,
  kPatches,
};

// The pattern named in the material table; an error names an unknown one.
Result<Pattern> parse_pattern(std::string_view name);

struct Texel {
  double shade = 1;  // ~[0.3, 1.5], multiplies the colour
  double mix = 0;    // [0, 1], blend towards the secondary colour
};

// (u, v): object coordinates, 1 unit = the image's shorter side at zoom 1. `seed` fixes the
// object's layout (knots, brick sizes, cell positions).
Texel pattern_texel(Pattern pattern, double u, double v, uint64_t seed);

// The pattern's second colour given the object colour.
std::array<double, 3> secondary_colour(Pattern pattern, const std::array<uint8_t, 3>& base,
                                       uint64_t seed);

}  // namespace tlvlink::sim::internal
