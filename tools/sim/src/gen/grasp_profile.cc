// The public oracle entry points: look the sensor up, then run the Monte Carlo of
// grasp_oracle.cc on its gel.

#include "gen/grasp_profile.h"

#include <algorithm>

#include "gen/grasp_oracle.h"
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
  TLV_ASSIGN_OR_RETURN(const SensorProfile profile, sensor_profile(options.sensor));
  return internal::oracle_report(internal::gel_contact_model(profile), options.seed, samples);
}

double grasp_oracle_accuracy(const GraspSetOptions& options, int64_t samples) {
  const Result<GraspOracleReport> r = grasp_oracle_report(options, samples);
  return r.ok() ? r.value().accuracy : 0.0;
}

}  // namespace tlvlink::sim
