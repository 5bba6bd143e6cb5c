// The extreme set: every case renders a finite uint8 frame of its sensor's size with finite
// ContactState, and the cases that promise a specific outcome show it.
#include <algorithm>
#include <map>
#include <memory>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "sim/render/render_test_util.h"
#include "tlvlink/sim/extreme.h"

namespace tlvlink::sim {
namespace {

TEST(SimRenderExtremeSet, HasTheNamedCasesOfTheIssue) {
  std::set<std::string_view> names;
  for (const ExtremeCase& c : extreme_cases()) {
    EXPECT_TRUE(names.insert(c.name).second) << "duplicate " << c.name;
    EXPECT_FALSE(c.what.empty());
    EXPECT_EQ(find_extreme_case(c.name), &c);
  }
  for (std::string_view required :
       {"no-contact", "saturated-leds", "leds-off", "full-frame-contact", "object-1kpa",
        "object-1e12pa", "mu-0", "point-contact", "step-edge", "jpeg-q1", "jpeg-q100", "gel-10kpa",
        "gel-10mpa"}) {
    EXPECT_TRUE(names.count(required)) << required;
  }
  EXPECT_EQ(find_extreme_case("no-such-case"), nullptr);
}

// Every case rendered once (a renderer is reused while the sensor profile stays the same).
const std::map<std::string_view, Frame>& rendered() {
  static const std::map<std::string_view, Frame> frames = [] {
    std::map<std::string_view, Frame> out;
    std::unique_ptr<Renderer> r;
    for (const ExtremeCase& c : extreme_cases()) {
      if (!r || !(r->profile() == c.sensor)) {
        auto created = Renderer::create(c.sensor, 17);
        EXPECT_TRUE(created.ok()) << c.name << ": " << created.error().message();
        if (!created.ok()) continue;
        r = std::move(created.value());
      }
      Frame f;
      const Status st = r->render(c.scene, c.options, 3, f);
      EXPECT_TRUE(st.ok()) << c.name << ": " << st.error().message();
      if (st.ok()) out.emplace(c.name, std::move(f));
    }
    return out;
  }();
  return frames;
}

TEST(SimRenderExtremeSet, EveryCaseGivesAFiniteFrameOfTheRightSize) {
  for (const ExtremeCase& c : extreme_cases()) {
    SCOPED_TRACE(std::string(c.name));
    ASSERT_TRUE(validate_all(c.sensor, c.scene, c.options).ok());
    const auto it = rendered().find(c.name);
    ASSERT_NE(it, rendered().end());
    const Frame& f = it->second;
    EXPECT_EQ(f.height, c.sensor.height);
    EXPECT_EQ(f.width, c.sensor.width);
    EXPECT_EQ(f.rgb.size(),
              static_cast<size_t>(c.sensor.height) * static_cast<size_t>(c.sensor.width) * 3);
    EXPECT_TRUE(testing::finite_state(f.state));
    EXPECT_GE(f.state.kappa, 0.0);
    EXPECT_LE(f.state.kappa, 1.0);
    if (c.scene.geometry.shape != Shape::kNone) {
      EXPECT_GT(f.state.kappa, 0.0);
    }
    EXPECT_GE(f.state.stick_radius_mm, 0.0);
    EXPECT_LE(f.state.stick_radius_mm, f.state.contact_radius_mm + 1e-12);
    for (const Marker& m : f.markers) {
      EXPECT_TRUE(std::isfinite(m.x) && std::isfinite(m.y)) << "marker";
    }
  }
}

const Frame& render_case(std::string_view name) {
  static const Frame kEmpty;
  const auto it = rendered().find(name);
  EXPECT_NE(it, rendered().end()) << name;
  return it == rendered().end() ? kEmpty : it->second;
}

double mean(const Frame& f) {
  double s = 0;
  for (uint8_t v : f.rgb) s += v;
  return s / static_cast<double>(f.rgb.size());
}

TEST(SimRenderExtremeSet, CasesShowTheirOutcome) {
  EXPECT_FALSE(render_case("no-contact").state.in_contact);
  EXPECT_FALSE(render_case("zero-force").state.in_contact);
  EXPECT_FALSE(render_case("object-outside-view").state.in_contact);
  EXPECT_LT(mean(render_case("leds-off")), 2.0);
  EXPECT_GT(mean(render_case("saturated-leds")), 240.0);
  const Frame& plate = render_case("full-frame-contact");
  EXPECT_NEAR(plate.state.contact_area_mm2, 240 * 320 * 0.0634 * 0.0634, 1e-6);
  EXPECT_TRUE(render_case("mu-0").state.gross_slip);
  EXPECT_FALSE(render_case("mu-0-no-shear").state.gross_slip);
  const Frame& point = render_case("point-contact");
  EXPECT_TRUE(point.state.in_contact);
  EXPECT_LT(point.state.contact_radius_mm, 2.0);
  EXPECT_TRUE(render_case("tiny-sphere").state.in_contact);
  // Depth limit: never more than 0.9 t_g in the gel.
  EXPECT_LE(render_case("max-press").state.max_gel_indentation_mm, 0.9 * 4.0 + 1e-6);
  EXPECT_LE(render_case("max-force").state.max_gel_indentation_mm, 0.9 * 4.0 + 1e-6);
  EXPECT_NE(render_case("jpeg-q1").rgb, render_case("jpeg-q100").rgb);
  EXPECT_TRUE(render_case("digit-640x480").state.in_contact);
  EXPECT_EQ(render_case("digit-640x480").rgb.size(), 640u * 480u * 3u);
}

TEST(SimRenderExtremeSet, JpegRoundTripChangesTheFrameByQuality) {
  const ExtremeCase* c = find_extreme_case("jpeg-q100");
  ASSERT_NE(c, nullptr);
  auto r = Renderer::create(c->sensor, 17);
  ASSERT_TRUE(r.ok());
  RenderOptions raw = c->options;
  raw.jpeg_quality = 0;
  Frame f0, f100, f1;
  ASSERT_TRUE(r.value()->render(c->scene, raw, 3, f0).ok());
  ASSERT_TRUE(r.value()->render(c->scene, c->options, 3, f100).ok());
  RenderOptions q1 = c->options;
  q1.jpeg_quality = 1;
  ASSERT_TRUE(r.value()->render(c->scene, q1, 3, f1).ok());
  const auto d100 = testing::diff_stats(f100.rgb, f0.rgb);
  const auto d1 = testing::diff_stats(f1.rgb, f0.rgb);
  EXPECT_LT(d100.stddev, 3.0);  // q100 with 4:2:0 chroma: a few DN
  EXPECT_GT(d1.stddev, d100.stddev);
}

}  // namespace
}  // namespace tlvlink::sim
