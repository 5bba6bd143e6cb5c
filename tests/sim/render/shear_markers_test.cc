// Markers and tangential contact: normal dilation, shear displacement, the shrinking stick
// region (Cattaneo-Mindlin), gross slip at rho >= 1, mu = 0, torsion and the slipping imprint.
#include <cmath>

#include <gtest/gtest.h>

#include "sim/render/render_test_util.h"

namespace tlvlink::sim {
namespace {

using testing::make_renderer;
using testing::quiet;
using testing::render_ok;
using testing::sphere;

RenderOptions with_markers() {
  RenderOptions o = quiet();
  o.markers = true;
  return o;
}

// A marker in double precision: rest position relative to the frame centre, displacement.
struct M {
  double rx, ry, dx, dy;
};
M as_double(const Marker& m) {
  const auto x0 = static_cast<double>(m.x0), y0 = static_cast<double>(m.y0);
  return {x0 - 159.5, y0 - 119.5, static_cast<double>(m.x) - x0, static_cast<double>(m.y) - y0};
}

// Mean marker displacement (px) of the markers within `radius_px` of the frame centre.
std::array<double, 2> mean_shift(const Frame& f, double radius_px) {
  double sx = 0, sy = 0;
  int n = 0;
  for (const Marker& marker : f.markers) {
    const M m = as_double(marker);
    if (std::hypot(m.rx, m.ry) > radius_px) continue;
    sx += m.dx;
    sy += m.dy;
    ++n;
  }
  return n > 0 ? std::array<double, 2>{sx / n, sy / n} : std::array<double, 2>{0, 0};
}

TEST(SimRenderMarkers, DrawnOnlyWhenAsked) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  EXPECT_TRUE(render_ok(*r, sphere(3), quiet()).markers.empty());
  const Frame f = render_ok(*r, sphere(3), with_markers());
  ASSERT_EQ(f.markers.size(), 63u);  // 7 x 9
  const double pitch_px = 2.2 / 0.0634;
  EXPECT_NEAR(f.markers[1].x0 - f.markers[0].x0, pitch_px, 1e-3);
  EXPECT_NEAR(f.markers[9].y0 - f.markers[0].y0, pitch_px, 1e-3);
  // A marker is a dark dot in the image.
  ContactScene empty;
  empty.geometry.shape = Shape::kNone;
  const Frame none = render_ok(*r, empty, with_markers());
  const Marker& m = none.markers[0];
  const size_t i =
      (static_cast<size_t>(std::lround(m.y)) * 320 + static_cast<size_t>(std::lround(m.x))) * 3;
  EXPECT_LT(none.rgb[i], r->background()[i] / 2);
}

TEST(SimRenderMarkers, PressDilatesTheGridOutward) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  const Frame f = render_ok(*r, sphere(8), with_markers());
  int outward = 0, near = 0;
  for (const Marker& marker : f.markers) {
    const M m = as_double(marker);
    const double d = std::hypot(m.rx, m.ry);
    if (d > 10 && d < 80) {
      ++near;
      outward += (m.rx * m.dx + m.ry * m.dy) > 0;
    }
    if (d > 200) {
      EXPECT_LT(std::hypot(m.dx, m.dy), 0.05);  // far markers do not move
    }
  }
  EXPECT_GT(near, 4);
  EXPECT_EQ(outward, near);
}

TEST(SimRenderShear, MovesMarkersAlongTheLoad) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  const Frame still = render_ok(*r, sphere(5), with_markers());
  ContactScene s = sphere(5);
  s.loading.shear_x_n = 1.0;
  const Frame sheared = render_ok(*r, s, with_markers());
  const auto a = mean_shift(still, 60), b = mean_shift(sheared, 60);
  EXPECT_GT(b[0] - a[0], 2.0);  // pixels, along +x
  EXPECT_NEAR(b[1] - a[1], 0.0, 0.5);
  EXPECT_GT(sheared.state.mean_shear_mm, 0.0);
  EXPECT_EQ(still.state.mean_shear_mm, 0.0);
  EXPECT_FALSE(sheared.state.gross_slip);
}

TEST(SimRenderShear, StickRegionShrinksAsTheLoadApproachesTheFrictionLimit) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  const Frame base = render_ok(*r, sphere(5), quiet());
  const double limit = 0.6 * base.state.force_n;  // mu P
  double prev_c = 1e9;
  for (double f : {0.0, 0.2, 0.5, 0.8, 0.95, 0.99}) {
    SCOPED_TRACE(f);
    ContactScene s = sphere(5);
    s.loading.shear_y_n = f * limit;
    const Frame fr = render_ok(*r, s, quiet());
    EXPECT_NEAR(fr.state.slip_ratio, f, 1e-9 + 1e-6 * f);
    const double a = fr.state.contact_radius_mm;
    // c = a (1 - rho)^(1/3)
    EXPECT_NEAR(fr.state.stick_radius_mm, a * std::cbrt(1 - f), 1e-9);
    EXPECT_LT(fr.state.stick_radius_mm, prev_c);
    EXPECT_FALSE(fr.state.gross_slip);
    prev_c = fr.state.stick_radius_mm;
  }
}

TEST(SimRenderShear, GrossSlipOnceRhoReachesOne) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  const double limit = 0.6 * render_ok(*r, sphere(5), quiet()).state.force_n;
  ContactScene s = sphere(5);
  s.loading.shear_x_n = 1.05 * limit;
  const Frame f = render_ok(*r, s, with_markers());
  EXPECT_TRUE(f.state.gross_slip);
  EXPECT_GE(f.state.slip_ratio, 1.0);
  EXPECT_EQ(f.state.stick_radius_mm, 0.0);
  // In gross slip the drag saturates: more load does not move the markers further.
  s.loading.shear_x_n = 3 * limit;
  const Frame g = render_ok(*r, s, with_markers());
  EXPECT_NEAR(g.state.mean_shear_mm, f.state.mean_shear_mm, 1e-6);
}

TEST(SimRenderShear, ZeroFrictionSlipsImmediately) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  ContactScene s = sphere(5);
  s.loading.friction = 0;
  s.loading.shear_x_n = 0.01;
  const Frame f = render_ok(*r, s, with_markers());
  EXPECT_TRUE(f.state.gross_slip);
  EXPECT_TRUE(std::isfinite(f.state.slip_ratio));
  s.loading.shear_x_n = 0;  // no tangential load: nothing to slip
  const Frame g = render_ok(*r, s, with_markers());
  EXPECT_FALSE(g.state.gross_slip);
  EXPECT_EQ(g.state.slip_ratio, 0.0);
}

TEST(SimRenderShear, TorqueTwistsTheMarkersItsWay) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  ContactScene s = sphere(8);
  s.loading.torque_nmm = 1.0;
  const Frame still = render_ok(*r, sphere(8), with_markers());
  const Frame f = render_ok(*r, s, with_markers());
  ASSERT_FALSE(f.state.gross_slip);
  double curl = 0;  // sum of r x d over the markers: > 0 for a positive (x -> y) twist
  for (size_t i = 0; i < f.markers.size(); ++i) {
    const M twisted = as_double(f.markers[i]), plain = as_double(still.markers[i]);
    curl += twisted.rx * (twisted.dy - plain.dy) - twisted.ry * (twisted.dx - plain.dx);
  }
  EXPECT_GT(curl, 0.0);
}

TEST(SimRenderShear, GrossSlipMovesTheImprintRelativeToTheGel) {
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  ContactScene s = sphere(5);
  s.loading.shear_x_n = 10;  // far beyond mu P = 3 N
  const Frame stay = render_ok(*r, s, quiet());
  s.loading.slip_mm = 2;
  const Frame slid = render_ok(*r, s, quiet());
  // Column centroid of the colour change moves by slip / (mm per px) along +x.
  auto centroid_x = [&](const Frame& f) {
    double sw = 0, sx = 0;
    for (int y = 0; y < f.height; ++y) {
      for (int x = 0; x < f.width; ++x) {
        for (int c = 0; c < 3; ++c) {
          const size_t i =
              (static_cast<size_t>(y) * 320 + static_cast<size_t>(x)) * 3 + static_cast<size_t>(c);
          const double d = std::abs(static_cast<int>(f.rgb[i]) - r->background()[i]);
          sw += d;
          sx += d * x;
        }
      }
    }
    return sx / sw;
  };
  constexpr double kTolerancePx = 3;  // background non-uniformity weights the centroid slightly
  EXPECT_NEAR(centroid_x(slid) - centroid_x(stay), 2 / 0.0634, kTolerancePx);
  EXPECT_TRUE(slid.state.gross_slip);
}

TEST(SimRenderShear, MarkersInTheSlipAnnulusDeviateFromTheRigidMotion) {
  // The incipient-slip cue: near the friction limit markers in the annulus lag the stick region.
  auto r = make_renderer("gelsight-mini");
  ASSERT_NE(r, nullptr);
  const double limit = 0.6 * render_ok(*r, sphere(10, 10), quiet()).state.force_n;
  ContactScene s = sphere(10, 10);
  EXPECT_EQ(render_ok(*r, s, quiet()).state.markers_deviating, 0);
  s.loading.shear_x_n = 0.1 * limit;
  const int low = render_ok(*r, s, quiet()).state.markers_deviating;
  s.loading.shear_x_n = 0.97 * limit;
  const int high = render_ok(*r, s, quiet()).state.markers_deviating;
  EXPECT_EQ(low, 0);
  EXPECT_GT(high, 0);
  // Gross slip with travel: every marker in the contact has lost the object.
  s.loading.shear_x_n = 2 * limit;
  s.loading.slip_mm = 3;
  const Frame slid = render_ok(*r, s, quiet());
  EXPECT_GT(slid.state.markers_deviating, high);
}

}  // namespace
}  // namespace tlvlink::sim
