// The hidden variables (mass, COM offset, lift acceleration) are independent of the visible
// ones (grip force, friction, contact areas, finger contact) under the prior, so
// P(success | visible) is the fraction of prior draws of the hidden variables that succeed with
// the visible ones fixed. The Bayes-optimal predictor says "success" when that is > 1/2.
// The same draws serve every episode (common random numbers), which makes the estimate smooth
// in the visible variables.

#include "gen/grasp_oracle.h"

#include <algorithm>

#include "gen/grasp_model.h"

namespace tlvlink::sim::internal {

HiddenDraws draw_hidden(uint64_t seed, int64_t count) {
  Rng rng(derive_seed(seed, {tag(Stream::kHidden)}));
  HiddenDraws h;
  const auto n = static_cast<size_t>(std::max<int64_t>(count, 0));
  h.mass_kg.resize(n);
  h.com_offset_mm.resize(n);
  h.lift_accel_mps2.resize(n);
  for (size_t i = 0; i < n; ++i) {
    h.mass_kg[i] = sample_mass(rng);
    sample_lift(rng, h.com_offset_mm[i], h.lift_accel_mps2[i]);
  }
  return h;
}

double success_probability(const GraspVariables& v, const HiddenDraws& hidden) {
  if (hidden.mass_kg.empty()) return 0;
  GraspVariables w = v;
  int64_t ok = 0;
  for (size_t i = 0; i < hidden.mass_kg.size(); ++i) {
    w.mass_kg = hidden.mass_kg[i];
    w.com_offset_mm = hidden.com_offset_mm[i];
    w.lift_accel_mps2 = hidden.lift_accel_mps2[i];
    ok += grasp_succeeds(w) ? 1 : 0;
  }
  return static_cast<double>(ok) / static_cast<double>(hidden.mass_kg.size());
}

void append_friction_slices(Range range, std::vector<double>& out) {
  const auto k = static_cast<double>(kOracleFrictionDraws);
  for (int64_t j = 0; j < kOracleFrictionDraws; ++j) {
    out.push_back(range.lo + (range.hi - range.lo) * (static_cast<double>(j) + 0.5) / k);
  }
}

std::vector<double> prior_friction_values() {
  std::vector<double> values;
  for (const int32_t cls : graspable_classes()) {
    append_friction_slices(material_class(cls).value()->friction, values);
  }
  return values;
}

double success_probability_class_friction(const GraspVariables& v, Range range,
                                          const HiddenDraws& hidden) {
  std::vector<double> values;
  append_friction_slices(range, values);
  return success_probability_over_friction(v, values, hidden);
}

double success_probability_over_friction(const GraspVariables& v, std::span<const double> frictions,
                                         const HiddenDraws& hidden) {
  const size_t n = hidden.mass_kg.size();
  if (n == 0 || frictions.empty()) return 0;
  GraspVariables w = v;
  int64_t ok = 0, total = 0;
  const size_t k = frictions.size();
  for (size_t j = 0; j < k; ++j) {
    w.friction = frictions[j];
    for (size_t i = j % n; i < n; i += k) {
      w.mass_kg = hidden.mass_kg[i];
      w.com_offset_mm = hidden.com_offset_mm[i];
      w.lift_accel_mps2 = hidden.lift_accel_mps2[i];
      ok += grasp_succeeds(w) ? 1 : 0;
      ++total;
    }
  }
  return total > 0 ? static_cast<double>(ok) / static_cast<double>(total) : 0.0;
}

GraspOracleReport oracle_report(const GelContactModel& gel, uint64_t seed, int64_t samples) {
  GraspOracleReport report;
  if (samples <= 0) return report;
  const uint64_t fresh = derive_seed(seed, {tag(Stream::kOracle)});  // not the dataset's items
  const HiddenDraws hidden = draw_hidden(fresh, kOracleHiddenDraws);
  const std::vector<double> prior_mu = prior_friction_values();
  int64_t correct = 0, class_correct = 0, prior_correct = 0, successes = 0;
  for (int64_t i = 0; i < samples; ++i) {
    const GraspObject object = sample_grasp_object(fresh, i);
    const GraspSetup setup = sample_grasp_setup(fresh, i);
    const GraspVariables v = grasp_variables(object, setup, gel);
    const bool label = grasp_succeeds(v);
    const bool predicted = success_probability(v, hidden) > 0.5;
    correct += predicted == label ? 1 : 0;
    successes += label ? 1 : 0;
    const Range mu = material_class(object.material.class_id).value()->friction;
    class_correct += (success_probability_class_friction(v, mu, hidden) > 0.5) == label ? 1 : 0;
    prior_correct +=
        (success_probability_over_friction(v, prior_mu, hidden) > 0.5) == label ? 1 : 0;
  }
  report.class_friction_accuracy =
      static_cast<double>(class_correct) / static_cast<double>(samples);
  report.prior_friction_accuracy =
      static_cast<double>(prior_correct) / static_cast<double>(samples);
  const auto n = static_cast<double>(samples);
  report.samples = samples;
  report.accuracy = static_cast<double>(correct) / n;
  report.success_rate = static_cast<double>(successes) / n;
  report.majority_rate = std::max(report.success_rate, 1.0 - report.success_rate);
  report.hidden_draws = kOracleHiddenDraws;
  return report;
}

}  // namespace tlvlink::sim::internal
