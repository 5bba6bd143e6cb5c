// Normal contact: force-depth monotonicity, the R1.5 calibration table, press/force modes, and
// the hardness cue (soft objects leave a flatter, shallower imprint).
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "render/model_constants.h"
#include "sim/render/render_test_util.h"

namespace tlvlink::sim {
namespace {

using testing::make_renderer;
using testing::quiet;
using testing::render_ok;
using testing::sphere;

TEST(SimRenderMechanics, DeeperPressGivesLargerContactAndIndentation) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  ContactState prev;
  for (double press : {0.05, 0.1, 0.2, 0.4, 0.7, 1.0, 1.5}) {
    SCOPED_TRACE(press);
    ContactScene s = sphere(-1);
    s.loading.press_mm = press;
    const Frame f = render_ok(*r, s, quiet());
    ASSERT_TRUE(f.state.in_contact);
    EXPECT_DOUBLE_EQ(f.state.press_mm, press);
    EXPECT_GT(f.state.contact_area_mm2, prev.contact_area_mm2);
    EXPECT_GT(f.state.max_gel_indentation_mm, prev.max_gel_indentation_mm);
    EXPECT_GT(f.state.force_n, prev.force_n);
    prev = f.state;
  }
}

TEST(SimRenderMechanics, ForceDepthIsMonotoneAndTheForceIsMet) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  // The bisection stops at |dF| < 1e-3 F; a pixel entering the contact adds a finite membrane
  // term, so allow 1 %.
  constexpr double kForceTolerance = 0.01;
  ContactState prev;
  for (double force : {0.2, 0.5, 1.0, 2.0, 4.0, 8.0, 15.0, 30.0}) {
    SCOPED_TRACE(force);
    ContactScene s = sphere(force, 8);
    s.texture.sq_um = 2;
    const Frame f = render_ok(*r, s, quiet());
    ASSERT_TRUE(f.state.in_contact);
    EXPECT_NEAR(f.state.force_n, force, kForceTolerance * force);
    EXPECT_GT(f.state.press_mm, prev.press_mm);
    EXPECT_GE(f.state.contact_area_mm2, prev.contact_area_mm2);
    prev = f.state;
  }
}

TEST(SimRenderMechanics, FollowsTheR15CalibrationTable) {
  // Taxim's GelSight R1.5 force-depth table (gelsight-sim.md) on the calibration sphere.
  auto r = make_renderer("gelsight-r1.5");
  ASSERT_NE(r, nullptr);
  constexpr double kDepthTolerance = 0.05;  // relative; the fit itself is within ~2 %
  const struct { double force_n, depth_mm; } table[] = {{1.1, 0.18}, {3.1, 0.38}, {5.9, 0.58}};
  for (const auto& row : table) {
    SCOPED_TRACE(row.force_n);
    const Frame f =
        render_ok(*r, sphere(row.force_n, internal::kCalibrationSphereRadiusMm), quiet());
    EXPECT_NEAR(f.state.max_gel_indentation_mm, row.depth_mm, kDepthTolerance * row.depth_mm);
  }
}

TEST(SimRenderMechanics, PressAndForceModesAgree) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  const Frame by_force = render_ok(*r, sphere(6), quiet());
  ContactScene s = sphere(-1);
  s.loading.press_mm = by_force.state.press_mm;
  const Frame by_press = render_ok(*r, s, quiet());
  constexpr double kTolerance = 1e-3;  // same depth, same pixels: same force up to rounding
  EXPECT_NEAR(by_press.state.force_n, by_force.state.force_n, kTolerance * 6);
  EXPECT_EQ(by_press.rgb, by_force.rgb);
}

TEST(SimRenderMechanics, SoftObjectsLeaveAFlatterShallowerImprint) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  ContactScene hard = sphere(5);
  hard.mechanics.modulus_pa = 70e9;
  ContactScene soft = sphere(5);
  soft.mechanics.modulus_pa = 50e3;
  soft.mechanics.poisson = 0.49;
  const Frame fh = render_ok(*r, hard, quiet());
  const Frame fs = render_ok(*r, soft, quiet());
  EXPECT_NEAR(fh.state.kappa, 1.0, 1e-4);
  EXPECT_LT(fs.state.kappa, 0.5);
  EXPECT_GT(fs.state.kappa, 0.0);
  EXPECT_LT(fs.state.max_gel_indentation_mm, 0.8 * fh.state.max_gel_indentation_mm);  // shallower
  EXPECT_GT(fs.state.contact_area_mm2, fh.state.contact_area_mm2);                    // flatter
  // Less relief, less shading: the strongest colour change is smaller.
  auto peak = [&](const Frame& f) {
    int best = 0;
    for (size_t i = 0; i < f.rgb.size(); ++i) {
      best = std::max(best, std::abs(static_cast<int>(f.rgb[i]) - r->background()[i]));
    }
    return best;
  };
  EXPECT_LT(peak(fs), peak(fh));
}

TEST(SimRenderMechanics, KappaStaysInTheUnitIntervalForAnyStiffness) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  double prev = 0;
  for (double e : {1e2, 1e3, 1e5, 1e7, 1e9, 1e11, 1e13}) {
    SCOPED_TRACE(e);
    ContactScene s = sphere(5);
    s.mechanics.modulus_pa = e;
    s.mechanics.poisson = 0.5;
    const Frame f = render_ok(*r, s, quiet());
    EXPECT_GT(f.state.kappa, prev);  // stiffer object: more of the approach goes into the gel
    EXPECT_LE(f.state.kappa, 1.0);
    EXPECT_TRUE(std::isfinite(f.state.press_mm));
    prev = f.state.kappa;
  }
}

}  // namespace
}  // namespace tlvlink::sim
