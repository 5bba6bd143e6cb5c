#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "grasp_oracle.h is internal to tools/sim: include its public headers instead"
#endif
// The Bayes-optimal grasp predictor from the visible variables alone, and its accuracy.

#include <cstdint>
#include <span>
#include <vector>

#include "gen/contact_area.h"
#include "tlvlink/sim/generate.h"

namespace tlvlink::sim::internal {

inline constexpr int64_t kOracleHiddenDraws = 4000;  // P(success | visible) to ~+-0.8 %
// Friction values per class (mid-points of equal slices of its uniform range) when mu is known
// only through the material class; with kOracleHiddenDraws / kOracleFrictionDraws hidden draws
// each, the estimate costs what the exact-mu one does.
inline constexpr int64_t kOracleFrictionDraws = 16;

// Precomputed draws of the hidden variables from their prior.
struct HiddenDraws {
  std::vector<double> mass_kg, com_offset_mm, lift_accel_mps2;
};
HiddenDraws draw_hidden(uint64_t seed, int64_t count);

// P(success | visible part of v), by Monte Carlo over `hidden` (v's hidden fields are ignored).
double success_probability(const GraspVariables& v, const HiddenDraws& hidden);
// The same with v.friction replaced by each of `frictions` in turn, value j with every k-th
// hidden draw from draw j mod n on (k = frictions.size(), n = the draws; when k <= n every draw
// is used once), i.e. mu marginalised over those values with equal weights.
double success_probability_over_friction(const GraspVariables& v, std::span<const double> frictions,
                                         const HiddenDraws& hidden);
// mu known only through the material class: kOracleFrictionDraws values spread over `range`
// (mid-points of equal slices of the class's uniform range).
double success_probability_class_friction(const GraspVariables& v, Range range,
                                          const HiddenDraws& hidden);
// mu known not at all: the grasp prior's friction (every graspable class, equally likely, each
// as kOracleFrictionDraws slices of its range).
std::vector<double> prior_friction_values();

// The oracle's accuracy on `samples` fresh episodes drawn from the grasp prior with `seed`.
GraspOracleReport oracle_report(const GelContactModel& gel, uint64_t seed, int64_t samples);

}  // namespace tlvlink::sim::internal
