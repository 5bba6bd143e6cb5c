// The public oracle entry points: look the sensor (or each profile of a mixed set) up, then run the
// Monte Carlo of grasp_oracle.cc on its gel.

#include "gen/grasp_profile.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "gen/grasp_oracle.h"
#include "gen/sensor_instances.h"
#include "tlvlink/sim/generate.h"

namespace tlvlink::sim {
namespace internal {

GelContactModel gel_contact_model(const SensorProfile& p) {
  GelContactModel gel;
  gel.height_mm = p.height * p.mm_per_px;
  gel.width_mm = p.width * p.mm_per_px;
  gel.gel_thickness_mm = p.gel_thickness_mm;
  gel.gel_modulus_pa = p.gel_modulus_pa;
  gel.gel_poisson = p.gel_poisson;
  // Cells of ~5 px (at most 64 x 80 of them, for speed) keep the area within a few % of the
  // rendered one.
  gel.grid_rows = std::clamp(p.height / 5, 8, 64);
  gel.grid_cols = std::clamp(p.width / 5, 8, 80);
  return gel;
}

}  // namespace internal

Result<GraspOracleReport> grasp_oracle_report(const GraspSetOptions& options, int64_t samples) {
  TLV_ENSURE(samples >= 0, ErrorCode::kInvalidArgument, "oracle: samples = %lld must be >= 0",
             static_cast<long long>(samples));
  const std::vector<std::string> names = internal::profile_names(options.sensor);
  if (names.size() == 1) {
    TLV_ASSIGN_OR_RETURN(const SensorProfile profile, sensor_profile(names[0]));
    return internal::oracle_report(internal::gel_contact_model(profile), options.seed, samples);
  }
  // A mixed-profile set draws each object's profile uniformly, and a frame shows its profile
  // (the frame size), so the oracle is each profile's, weighted by its share of the samples.
  GraspOracleReport mixed;
  const auto n = static_cast<int64_t>(names.size());
  for (int64_t k = 0; k < n; ++k) {
    TLV_ASSIGN_OR_RETURN(const SensorProfile profile,
                         sensor_profile(names[static_cast<size_t>(k)]));
    const int64_t share = samples / n + (k < samples % n ? 1 : 0);
    if (share == 0) continue;
    const GraspOracleReport r =
        internal::oracle_report(internal::gel_contact_model(profile), options.seed, share);
    const auto w = static_cast<double>(r.samples);
    mixed.samples += r.samples;
    mixed.accuracy += w * r.accuracy;
    mixed.success_rate += w * r.success_rate;
    mixed.class_friction_accuracy += w * r.class_friction_accuracy;
    mixed.prior_friction_accuracy += w * r.prior_friction_accuracy;
    mixed.hidden_draws = r.hidden_draws;
  }
  if (mixed.samples > 0) {
    const auto total = static_cast<double>(mixed.samples);
    mixed.accuracy /= total;
    mixed.success_rate /= total;
    mixed.class_friction_accuracy /= total;
    mixed.prior_friction_accuracy /= total;
    mixed.majority_rate = std::max(mixed.success_rate, 1 - mixed.success_rate);
  }
  return mixed;
}

Result<std::vector<double>> grasp_success_given_class_weights(
    std::span<const GraspVariables> episodes,
    std::span<const std::array<double, kMaterialClassCount>> class_weights, uint64_t seed) {
  TLV_ENSURE(episodes.size() == class_weights.size(), ErrorCode::kInvalidArgument,
             "grasp success: %zu episodes but %zu rows of class weights", episodes.size(),
             class_weights.size());
  for (size_t i = 0; i < class_weights.size(); ++i) {
    double sum = 0;
    for (const double w : class_weights[i]) {
      TLV_ENSURE(w >= 0 && std::isfinite(w), ErrorCode::kInvalidArgument,
                 "grasp success: episode %zu has a class weight %g (must be finite, >= 0)", i, w);
      sum += w;
    }
    TLV_ENSURE(std::fabs(sum - 1) <= 1e-6, ErrorCode::kInvalidArgument,
               "grasp success: episode %zu's class weights sum to %.9g, not 1", i, sum);
  }
  const internal::HiddenDraws hidden = internal::draw_hidden(seed, internal::kOracleHiddenDraws);
  std::vector<double> out(episodes.size(), 0.0);
  for (size_t i = 0; i < episodes.size(); ++i) {
    for (int32_t c = 0; c < kMaterialClassCount; ++c) {
      const double w = class_weights[i][static_cast<size_t>(c)];
      if (w <= 0) continue;
      TLV_ASSIGN_OR_RETURN(const MaterialClass* cls, material_class(c));
      out[i] +=
          w * internal::success_probability_class_friction(episodes[i], cls->friction, hidden);
    }
  }
  return out;
}

double grasp_oracle_accuracy(const GraspSetOptions& options, int64_t samples) {
  const Result<GraspOracleReport> r = grasp_oracle_report(options, samples);
  return r.ok() ? r.value().accuracy : 0.0;
}

}  // namespace tlvlink::sim
