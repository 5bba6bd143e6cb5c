// The public oracle entry points: look the sensor (or each profile of a mixed set) up, then run the
// Monte Carlo of grasp_oracle.cc on its gel.

#include "gen/grasp_profile.h"

#include <algorithm>
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

double grasp_oracle_accuracy(const GraspSetOptions& options, int64_t samples) {
  const Result<GraspOracleReport> r = grasp_oracle_report(options, samples);
  return r.ok() ? r.value().accuracy : 0.0;
}

}  // namespace tlvlink::sim
