// The grasp rule (friction limit), the contact-area model behind the visible variables, the
// label balance of the grasp prior, and the oracle's accuracy.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "gen/contact_area.h"
#include "gen/grasp_model.h"
#include "gen/grasp_oracle.h"
#include "support/random.h"
#include "tlvlink/sim/generate.h"

namespace tlvlink::sim {
namespace {

using internal::GelContactModel;

// Label balance and oracle over this many fresh episodes: the standard error of a rate is
// <= 0.5 / sqrt(1500) ~ 0.013, small against the bands below.
constexpr int64_t kOracleSamples = 1500;

GraspVariables held_grasp() {
  GraspVariables v;
  v.grip_force_n = 20;
  v.friction = 0.8;
  v.contact_area_mm2[0] = v.contact_area_mm2[1] = 100;
  v.mass_kg = 0.2;
  v.com_offset_mm = 2;
  v.lift_accel_mps2 = 1;
  return v;
}

TEST(GraspRule, EdgeCases) {
  GraspVariables v = held_grasp();
  EXPECT_TRUE(grasp_succeeds(v));

  GraspVariables no_friction = v;
  no_friction.friction = 0;
  EXPECT_FALSE(grasp_succeeds(no_friction));
  EXPECT_EQ(grasp_slip_ratio(no_friction), kMaxSlipRatio);

  GraspVariables weightless = v;
  weightless.mass_kg = 0;
  weightless.friction = 0;
  EXPECT_TRUE(grasp_succeeds(weightless)) << "nothing to hold";
  EXPECT_EQ(grasp_slip_ratio(weightless), 0);

  for (int f = 0; f < kFingers; ++f) {
    GraspVariables missing = v;
    missing.finger_in_contact[f] = false;
    missing.contact_area_mm2[f] = 0;
    EXPECT_FALSE(grasp_succeeds(missing));
    missing.mass_kg = 0;
    EXPECT_FALSE(grasp_succeeds(missing)) << "one finger cannot lift even a weightless object";
  }

  GraspVariables no_grip = v;
  no_grip.grip_force_n = 0;
  EXPECT_FALSE(grasp_succeeds(no_grip));

  // Point contact with a COM offset: no torsional capacity.
  GraspVariables point = v;
  point.contact_area_mm2[0] = 0;
  EXPECT_FALSE(grasp_succeeds(point));
  EXPECT_TRUE(std::isfinite(grasp_slip_ratio(point)));
  point.com_offset_mm = 0;
  EXPECT_TRUE(grasp_succeeds(point)) << "no torque, translation alone is held";
}

TEST(GraspRule, SlipRatioFollowsTheFormulaAndTheBoundaryHolds) {
  GraspVariables v = held_grasp();
  const double q = v.mass_kg * (kGravity + v.lift_accel_mps2) / 2;
  const double m = v.mass_kg * kGravity * v.com_offset_mm / 2;
  const double a = std::sqrt(100 / std::numbers::pi);
  const double expected =
      std::hypot(q / (0.8 * 20), m / (3 * std::numbers::pi / 16 * 0.8 * 20 * a));
  EXPECT_NEAR(grasp_slip_ratio(v), expected, 1e-12);
  // Scale the mass so rho is exactly 1 (rho is linear in m): held at 1, dropped just above.
  v.mass_kg *= 1.0 / expected;
  EXPECT_NEAR(grasp_slip_ratio(v), 1.0, 1e-12);
  v.mass_kg *= 1 - 1e-9;
  EXPECT_TRUE(grasp_succeeds(v));
  v.mass_kg *= 1 + 1e-6;
  EXPECT_FALSE(grasp_succeeds(v));
  // More grip or friction only helps.
  GraspVariables w = held_grasp();
  w.mass_kg = 1.5;
  w.com_offset_mm = 20;
  w.grip_force_n = 5;
  double last = grasp_slip_ratio(w);
  for (double p = 6; p <= 35; p += 1) {
    w.grip_force_n = p;
    EXPECT_LE(grasp_slip_ratio(w), last);
    last = grasp_slip_ratio(w);
  }
}

TEST(ContactArea, BehavesLikeTheRenderersModel) {
  const GelContactModel gel;
  ObjectGeometry sphere;
  sphere.shape = Shape::kSphere;
  sphere.radius_mm = 20;
  ObjectMechanics hard;  // 70 GPa
  ObjectMechanics soft;
  soft.modulus_pa = 5e4;
  soft.poisson = 0.45;
  soft.local_radius_mm = 20;
  EXPECT_EQ(internal::contact_area_mm2(gel, sphere, hard, 0), 0);
  ObjectGeometry none;
  none.shape = Shape::kNone;
  EXPECT_EQ(internal::contact_area_mm2(gel, none, hard, 10), 0);
  double last = 0;
  for (double f : {0.5, 2.0, 5.0, 10.0, 20.0}) {
    const double a = internal::contact_area_mm2(gel, sphere, hard, f);
    EXPECT_GT(a, last) << "area grows with force";
    last = a;
  }
  // A soft object shares the indentation: a deeper approach, a larger contact.
  EXPECT_GT(internal::contact_area_mm2(gel, sphere, soft, 5),
            1.5 * internal::contact_area_mm2(gel, sphere, hard, 5));
  EXPECT_GT(internal::compliance_split(gel, hard), 0.99);
  EXPECT_LT(internal::compliance_split(gel, soft), 0.5);
  ObjectGeometry flat;
  flat.shape = Shape::kFlatPlate;
  EXPECT_NEAR(internal::contact_area_mm2(gel, flat, hard, 5), gel.height_mm * gel.width_mm, 1e-6);
  ObjectGeometry edge;
  edge.shape = Shape::kBoxEdge;
  EXPECT_NEAR(internal::contact_area_mm2(gel, edge, hard, 5), 0.5 * gel.height_mm * gel.width_mm,
              0.05 * gel.height_mm * gel.width_mm);
}

TEST(GraspPrior, LabelIsBalancedAndTheOracleIsInformativeButNotPerfect) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  const GraspOracleReport r = internal::oracle_report(GelContactModel{}, seed, kOracleSamples);
  std::printf(
      "grasp prior: success %.3f, oracle accuracy %.3f (majority %.3f) over %lld episodes\n",
      r.success_rate, r.accuracy, r.majority_rate, static_cast<long long>(r.samples));
  EXPECT_EQ(r.samples, kOracleSamples);
  EXPECT_GE(r.success_rate, 0.40);
  EXPECT_LE(r.success_rate, 0.60);
  // Above chance and clearly above "always the majority": the during frames carry real
  // information (grip, friction, area). Below 0.98: mass, COM offset and lift acceleration are
  // hidden and move rho by a large factor, so a band of visible configurations stays uncertain.
  EXPECT_GT(r.accuracy, 0.6);
  EXPECT_LT(r.accuracy, 0.98);
  EXPECT_GT(r.accuracy, r.majority_rate + 0.1);
}

TEST(GraspPrior, SamplingIsDeterministicAndSuccessProbabilityIsSane) {
  const internal::GraspObject a = internal::sample_grasp_object(5, 3),
                              b = internal::sample_grasp_object(5, 3);
  EXPECT_EQ(a.mass_kg, b.mass_kg);
  EXPECT_EQ(a.material.modulus_pa, b.material.modulus_pa);
  const internal::GraspSetup s = internal::sample_grasp_setup(5, 7);
  const GraspVariables v1 = internal::grasp_variables(a, s, GelContactModel{});
  const GraspVariables v2 = internal::grasp_variables(a, s, GelContactModel{});
  EXPECT_EQ(v1.contact_area_mm2[0], v2.contact_area_mm2[0]);
  EXPECT_EQ(v1.slip_ratio, v2.slip_ratio);

  const internal::HiddenDraws hidden = internal::draw_hidden(1, 2000);
  GraspVariables strong = held_grasp();
  strong.grip_force_n = 35;
  strong.friction = 1.2;
  strong.contact_area_mm2[0] = strong.contact_area_mm2[1] = 300;
  GraspVariables weak = held_grasp();
  weak.grip_force_n = 5;
  weak.friction = 0.2;
  weak.contact_area_mm2[0] = weak.contact_area_mm2[1] = 20;
  EXPECT_GT(internal::success_probability(strong, hidden), 0.8);
  EXPECT_LT(internal::success_probability(weak, hidden), 0.2);
  GraspVariables missing = strong;
  missing.finger_in_contact[1] = false;
  EXPECT_EQ(internal::success_probability(missing, hidden), 0);
  EXPECT_EQ(internal::oracle_report(GelContactModel{}, 1, 0).samples, 0);

  // Friction marginalised over a list of values: one value is the exact-mu estimate (the same
  // draws), a slippery and a grippy value land between the two.
  const double mu_weak[] = {0.2}, mu_strong[] = {1.2}, mu_both[] = {0.2, 1.2};
  GraspVariables mid = held_grasp();
  mid.grip_force_n = 15;
  mid.contact_area_mm2[0] = mid.contact_area_mm2[1] = 100;
  mid.friction = 0.2;
  const double p_weak = internal::success_probability(mid, hidden);
  mid.friction = 1.2;
  const double p_strong = internal::success_probability(mid, hidden);
  EXPECT_EQ(internal::success_probability_over_friction(mid, mu_weak, hidden), p_weak);
  EXPECT_EQ(internal::success_probability_over_friction(mid, mu_strong, hidden), p_strong);
  ASSERT_LT(p_weak, p_strong);
  const double p_both = internal::success_probability_over_friction(mid, mu_both, hidden);
  EXPECT_GT(p_both, p_weak);
  EXPECT_LT(p_both, p_strong);
  EXPECT_EQ(internal::success_probability_over_friction(mid, {}, hidden), 0);
  // The prior's values: 16 slices of each graspable class's range.
  const std::vector<double> prior = internal::prior_friction_values();
  EXPECT_EQ(prior.size(), internal::graspable_classes().size() *
                              static_cast<size_t>(internal::kOracleFrictionDraws));
  for (double mu : prior) {
    EXPECT_GT(mu, 0.1);
    EXPECT_LT(mu, 1.25);
  }
}

}  // namespace
}  // namespace tlvlink::sim
