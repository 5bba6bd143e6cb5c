// Issue 16's two departures from the first renderer, both for soft objects: a compliant layer
// bottoms out (it cannot be compressed beyond kMaxLayerStrain of its thickness) and an object's
// texture is shared with the gel at its own length scale (soft textures flatten more than the
// bulk). Stiff objects must render exactly as before.
#include <cmath>
#include <cstdlib>

#include <gtest/gtest.h>

#include "render/contact.h"
#include "render/model_constants.h"
#include "sim/render/render_test_util.h"

namespace tlvlink::sim {
namespace {

using testing::make_renderer;
using testing::quiet;
using testing::render_ok;
using testing::sphere;

// A fabric-like layer: 30 kPa, 1 mm thick on a rigid backing, pressed by a 10 mm ball.
ContactScene fabric(double force_n, double layer_mm) {
  ContactScene s = sphere(force_n, 10);
  s.mechanics.modulus_pa = 30e3;
  s.mechanics.poisson = 0.4;
  s.mechanics.local_radius_mm = 1.0;  // compliant_length_mm: the layer, thinner than the ball
  s.mechanics.layer_mm = layer_mm;
  s.texture.sq_um = 0;
  return s;
}

TEST(SimRenderSoftLayers, ALayerBottomsOutAndTheGelTakesTheRest) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  // Without the cap the 30 kPa layer would take (1 - kappa) of the approach whatever its
  // thickness; with it, at most 0.6 mm of a 1 mm layer.
  const Frame unbounded = render_ok(*r, fabric(8, 0), quiet());
  const Frame capped = render_ok(*r, fabric(8, 1.0), quiet());
  const double kappa = capped.state.kappa;
  ASSERT_LT(kappa, 0.6);
  const double object_unbounded = unbounded.state.press_mm - unbounded.state.max_gel_indentation_mm;
  ASSERT_GT(object_unbounded, internal::kMaxLayerStrain * 1.0) << "the cap must matter here";
  const double object_capped = capped.state.press_mm - capped.state.max_gel_indentation_mm;
  constexpr double kBisection = 0.02;  // mm: force tolerance 1e-3 F on this press
  EXPECT_LE(object_capped, internal::kMaxLayerStrain * 1.0 + kBisection);
  // The same force now needs less approach and indents the gel deeper (the backing shows).
  EXPECT_GT(capped.state.max_gel_indentation_mm, unbounded.state.max_gel_indentation_mm);
  EXPECT_NEAR(capped.state.force_n, 8, 0.01 * 8);
  EXPECT_NE(capped.rgb, unbounded.rgb);
}

TEST(SimRenderSoftLayers, BelowTheCapNothingChanges) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  // A 5 mm layer is never compressed by 3 mm at 1 N: the cap cannot be reached.
  ContactScene thick = fabric(1, 5.0);
  thick.mechanics.local_radius_mm = 5.0;
  ContactScene bulk = thick;
  bulk.mechanics.layer_mm = 0;
  EXPECT_EQ(render_ok(*r, thick, quiet()).rgb, render_ok(*r, bulk, quiet()).rgb);
}

TEST(SimRenderSoftLayers, StiffObjectsRenderAsBefore) {
  // A stiff object's texture split and bulk split agree to < kTextureSplitTolerance and a layer
  // of it never reaches its cap: its frames must not depend on either change.
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  ContactScene rock = sphere(6, 8);
  rock.mechanics.modulus_pa = 3e10;
  rock.texture.sq_um = 40;
  rock.texture.correlation_length_mm = 0.8;
  ContactScene layered = rock;
  layered.mechanics.layer_mm = 2;
  const Frame a = render_ok(*r, rock, quiet()), b = render_ok(*r, layered, quiet());
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_NEAR(a.state.texture_kappa, 1.0, 1e-5);
  EXPECT_NEAR(a.state.texture_kappa / a.state.kappa, 1.0, internal::kTextureSplitTolerance);
}

TEST(SimRenderSoftLayers, SoftTexturesFlattenMoreThanTheBulk) {
  // At its 0.5 mm correlation length a 100 kPa texture shares the load with the gel as two
  // half-spaces do; the 1 mm layer as a whole is stiffer against the 4 mm gel.
  const SensorProfile mini = sensor_profile("gelsight-mini").value();
  ObjectMechanics m;
  m.modulus_pa = 100e3;
  m.poisson = 0.4;
  m.local_radius_mm = 1.0;
  m.layer_mm = 1.0;
  SurfaceTexture t;
  t.correlation_length_mm = 0.5;
  const double cg = (1 - 0.485 * 0.485) / 150e3, co = (1 - 0.4 * 0.4) / 100e3;
  EXPECT_NEAR(internal::texture_split(mini, m, t), cg / (cg + co), 1e-9);
  EXPECT_NEAR(internal::compliance(mini, m).kappa, 4 * cg / (4 * cg + co), 1e-9);
  EXPECT_LT(internal::texture_split(mini, m, t), 0.7 * internal::compliance(mini, m).kappa);
  // A texture coarser than the layer is thick feels the layer (and the gel its own thickness).
  t.correlation_length_mm = 3.0;
  EXPECT_NEAR(internal::texture_split(mini, m, t), 3 * cg / (3 * cg + co), 1e-9);

  // Rendered: the same rough 100 kPa fabric shows less texture than the bulk split would give.
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  ContactScene s;
  s.geometry.shape = Shape::kFlatPlate;
  s.loading.force_n = 6;
  s.mechanics = m;
  s.mechanics.layer_mm = 0;  // keep the bulk uncapped: only the texture differs below
  s.texture.sq_um = 30;
  s.texture.correlation_length_mm = 0.5;
  const Frame f = render_ok(*r, s, quiet());
  EXPECT_NEAR(f.state.texture_kappa, cg / (cg + (1 - 0.16) / 100e3), 1e-9);
  // The plate's contrast: spread of the frame around the background.
  auto spread = [&](const Frame& frame) {
    double ss = 0;
    for (size_t i = 0; i < frame.rgb.size(); ++i) {
      const double d = static_cast<double>(frame.rgb[i]) - r->background()[i];
      ss += d * d;
    }
    return std::sqrt(ss / static_cast<double>(frame.rgb.size()));
  };
  ContactScene hard = s;
  hard.mechanics.modulus_pa = 5e9;
  EXPECT_LT(spread(f), 0.8 * spread(render_ok(*r, hard, quiet())));
}

}  // namespace
}  // namespace tlvlink::sim
