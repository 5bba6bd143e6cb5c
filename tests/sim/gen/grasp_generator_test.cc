// The grasp-episode generator: sizes, determinism, order independence, frames that agree with
// the label, visible variables that agree with the rendered contact, and the public oracle.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "support/random.h"
#include "tlvlink/sim/generate.h"
#include "tlvlink/sim/live_path.h"

namespace tlvlink::sim {
namespace {

// The contact-area model is a coarse copy of the renderer's mechanics (5 px cells, no texture):
// its area agrees with the rendered one to within this fraction (median over episodes).
constexpr double kAreaAgreement = 0.15;
// The renderer's slip ratio at the lift equals the label's rho up to the force bisection
// tolerance (1e-3) and float rounding.
constexpr double kRhoAgreement = 0.01;

GraspSetOptions small_grasp_options(uint64_t seed) {
  GraspSetOptions o;
  o.objects = 4;
  o.grasps_per_object = 3;
  o.vision_height = 24;
  o.vision_width = 32;
  o.seed = seed;
  return o;
}

std::unique_ptr<GraspEpisodeGenerator> make(const GraspSetOptions& o) {
  auto g = GraspEpisodeGenerator::create(o);
  EXPECT_TRUE(g.ok()) << (g.ok() ? "" : g.error().message());
  return g.ok() ? std::move(g).value() : nullptr;
}

const ContactState& state(const GraspEpisode& e, int f, Moment m) {
  return e.states[f][static_cast<int>(m)];
}

TEST(GraspGenerator, FramesAgreeWithTheLabel) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  GraspSetOptions o = small_grasp_options(seed);
  o.objects = 8;
  auto gen = make(o);
  ASSERT_NE(gen, nullptr);
  ASSERT_EQ(gen->size(), 24);
  GraspEpisode e;
  std::vector<double> area_error;
  int held = 0;
  for (int64_t i = 0; i < gen->size(); ++i) {
    SCOPED_TRACE("episode " + std::to_string(i));
    ASSERT_TRUE(gen->generate(i, e).ok());
    const GraspVariables& v = e.variables;
    EXPECT_EQ(e.is_gripping, grasp_succeeds(v));
    EXPECT_EQ(v.slip_ratio, grasp_slip_ratio(v));
    EXPECT_DOUBLE_EQ(v.margin, 1 - v.slip_ratio);
    EXPECT_GE(v.grip_force_n, 5);
    EXPECT_LE(v.grip_force_n, 35);
    EXPECT_GT(v.mass_kg, 0);
    EXPECT_EQ(e.object_id, i / 3);
    held += e.is_gripping;
    for (int f = 0; f < kFingers; ++f) {
      for (int m = 0; m < kMoments; ++m) {
        EXPECT_EQ(e.frames[f][m].rgb.size(), 240u * 320u * 3u);
        EXPECT_EQ(e.vision[m].rgb.size(), 24u * 32u * 3u);
        EXPECT_TRUE(std::isfinite(e.states[f][m].slip_ratio));
      }
      EXPECT_FALSE(state(e, f, Moment::kBefore).in_contact);
      EXPECT_EQ(state(e, f, Moment::kDuring).in_contact, v.finger_in_contact[f]);
      EXPECT_LT(state(e, f, Moment::kDuring).slip_ratio, 1) << "the resting object does not slip";
      if (v.finger_in_contact[f]) {
        const double rendered = state(e, f, Moment::kDuring).contact_area_mm2;
        area_error.push_back(std::fabs(v.contact_area_mm2[f] - rendered) / rendered);
      }
      const ContactState& after = state(e, f, Moment::kAfter);
      if (e.is_gripping) {
        EXPECT_TRUE(after.in_contact);
        EXPECT_FALSE(after.gross_slip);
        EXPECT_LE(after.slip_ratio, 1);
      } else if (v.finger_in_contact[0] && v.finger_in_contact[1] && v.slip_ratio < 3) {
        EXPECT_TRUE(after.gross_slip);
        EXPECT_NEAR(after.slip_ratio, v.slip_ratio, kRhoAgreement * v.slip_ratio);
      } else {
        EXPECT_FALSE(after.in_contact) << "dropped";
      }
    }
    if (e.is_gripping) {  // the finger with the larger rho carries the label's rho
      const double rendered =
          std::max(state(e, 0, Moment::kAfter).slip_ratio, state(e, 1, Moment::kAfter).slip_ratio);
      EXPECT_NEAR(rendered, std::min(v.slip_ratio, 0.999), kRhoAgreement);
    }
  }
  std::sort(area_error.begin(), area_error.end());
  const double median = area_error[area_error.size() / 2];
  std::printf("grasp: %d/24 held; contact area model vs rendered: median error %.3f, max %.3f\n",
              held, median, area_error.back());
  EXPECT_LT(median, kAreaAgreement);
}

TEST(GraspGenerator, DeterministicAndIndependentOfOrder) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  auto a = make(small_grasp_options(seed)), b = make(small_grasp_options(seed));
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  GraspEpisode x, y, first;
  ASSERT_TRUE(a->generate(0, first).ok());
  for (int64_t i : {7, 3}) {
    ASSERT_TRUE(a->generate(i, x).ok());
    for (int64_t j = 11; j > i; --j) ASSERT_TRUE(b->generate(j, y).ok());  // b has another history
    ASSERT_TRUE(b->generate(i, y).ok());
    EXPECT_EQ(x.object_name, y.object_name);
    EXPECT_EQ(x.is_gripping, y.is_gripping);
    EXPECT_EQ(x.variables.mass_kg, y.variables.mass_kg);
    for (int f = 0; f < kFingers; ++f) {
      for (int m = 0; m < kMoments; ++m) EXPECT_EQ(x.frames[f][m].rgb, y.frames[f][m].rgb);
    }
    EXPECT_EQ(x.vision[2].rgb, y.vision[2].rgb);
  }
  // Grasps of one object share the object (name, material, mass), not the grasp.
  GraspEpisode g0, g1, g3;
  ASSERT_TRUE(a->generate(0, g0).ok());
  ASSERT_TRUE(a->generate(1, g1).ok());
  ASSERT_TRUE(a->generate(3, g3).ok());
  EXPECT_EQ(g0.object_name, g1.object_name);
  EXPECT_EQ(g0.variables.mass_kg, g1.variables.mass_kg);
  EXPECT_EQ(g0.material.friction, g1.material.friction);
  EXPECT_NE(g0.object_name, g3.object_name);
  EXPECT_EQ(g0.frames[0][0].rgb, first.frames[0][0].rgb);
}

TEST(GraspGenerator, OracleFromThePublicApi) {
  GraspSetOptions o = small_grasp_options(testing::test_seed());
  const Result<GraspOracleReport> r = grasp_oracle_report(o, 600);
  ASSERT_TRUE(r.ok());
  EXPECT_GT(r.value().accuracy, 0.6);
  EXPECT_LT(r.value().accuracy, 0.98);
  // Less known of the friction, less accuracy: exact mu >= mu via the class >= mu unknown, up
  // to the Monte Carlo noise of 600 episodes and 4,000 hidden draws (~2 points).
  EXPECT_LE(r.value().class_friction_accuracy, r.value().accuracy + 0.02);
  EXPECT_LE(r.value().prior_friction_accuracy, r.value().class_friction_accuracy + 0.02);
  EXPECT_GT(r.value().prior_friction_accuracy, r.value().majority_rate - 0.02);
  EXPECT_EQ(grasp_oracle_accuracy(o, 600), r.value().accuracy);
  o.sensor = "no-such-sensor";
  EXPECT_EQ(grasp_oracle_accuracy(o, 100), 0);
  EXPECT_FALSE(grasp_oracle_report(o, 100).ok());
}

TEST(GraspGenerator, MixedProfileSetsDrawAProfilePerObject) {
  // "gelsight-mini,digit": every grasp of an object on one profile, both fingers alike; an
  // object's Mini episodes are the bytes (and the variables) a Mini-only set of the seed gives.
  GraspSetOptions mixed = small_grasp_options(5);
  mixed.objects = 10;
  mixed.grasps_per_object = 2;
  mixed.sensor = "gelsight-mini,digit";
  GraspSetOptions mini = mixed;
  mini.sensor = "gelsight-mini";
  auto g = make(mixed), m = make(mini);
  ASSERT_NE(g, nullptr);
  ASSERT_NE(m, nullptr);
  std::set<std::string> seen;
  GraspEpisode e, t, first;
  for (int64_t i = 0; i < g->size(); ++i) {
    ASSERT_TRUE(g->generate(i, e).ok());
    seen.insert(e.sensor);
    if (i % 2 == 1) {
      ASSERT_TRUE(g->generate(i - 1, first).ok());
      EXPECT_EQ(first.sensor, e.sensor) << "episode " << i;
    }
    if (e.sensor == "gelsight-mini") {
      ASSERT_TRUE(m->generate(i, t).ok());
      EXPECT_EQ(t.sensor, "gelsight-mini");
      EXPECT_EQ(e.is_gripping, t.is_gripping);
      EXPECT_EQ(e.variables.contact_area_mm2[0], t.variables.contact_area_mm2[0]);
      for (int f = 0; f < kFingers; ++f)
        for (int k = 0; k < kMoments; ++k) EXPECT_EQ(e.frames[f][k].rgb, t.frames[f][k].rgb);
    } else {
      EXPECT_EQ(e.sensor, "digit");
      for (int f = 0; f < kFingers; ++f) {  // DIGIT frames are portrait (tools/sim/REFERENCE.md)
        EXPECT_EQ(e.frames[f][0].height, 320);
        EXPECT_EQ(e.frames[f][0].width, 240);
      }
    }
  }
  EXPECT_EQ(seen.size(), 2u) << "10 objects should draw both profiles";
  // The oracle of a mixed set lies between its profiles' (the average of the two).
  const auto both = grasp_oracle_report(mixed, 2000), one = grasp_oracle_report(mini, 1000);
  GraspSetOptions digit = mixed;
  digit.sensor = "digit";
  const auto other = grasp_oracle_report(digit, 1000);
  ASSERT_TRUE(both.ok() && one.ok() && other.ok());
  EXPECT_EQ(both->samples, 2000);
  EXPECT_NEAR(both->accuracy, (one->accuracy + other->accuracy) / 2, 1e-9);
  mixed.sensor = "gelsight-mini,nosuch";
  EXPECT_FALSE(GraspEpisodeGenerator::create(mixed).ok());
  EXPECT_FALSE(grasp_oracle_report(mixed, 100).ok());
}

TEST(GraspGenerator, MarkersFractionDrawsMarkedGelsPerObject) {
  // Half the objects on gels with markers: their frames differ from the unmarked set's, the
  // others' are the same bytes; every grasp of an object agrees.
  GraspSetOptions half = small_grasp_options(9);
  half.objects = 12;
  half.grasps_per_object = 2;
  half.markers = false;
  half.markers_fraction = 0.5;
  GraspSetOptions none = half;
  none.markers_fraction = 0;
  auto g = make(half), n = make(none);
  ASSERT_NE(g, nullptr);
  ASSERT_NE(n, nullptr);
  int marked = 0;
  GraspEpisode a, b;
  for (int64_t object = 0; object < half.objects; ++object) {
    bool differs[2];
    for (int64_t k = 0; k < 2; ++k) {
      ASSERT_TRUE(g->generate(object * 2 + k, a).ok());
      ASSERT_TRUE(n->generate(object * 2 + k, b).ok());
      differs[k] = a.frames[0][0].rgb != b.frames[0][0].rgb;  // the open gel shows the grid
      EXPECT_EQ(a.is_gripping, b.is_gripping);
    }
    EXPECT_EQ(differs[0], differs[1]) << "object " << object;
    marked += differs[0] ? 1 : 0;
  }
  EXPECT_GT(marked, 0);
  EXPECT_LT(marked, half.objects);
  half.markers_fraction = 1.5;
  EXPECT_EQ(GraspEpisodeGenerator::create(half).error().code(), ErrorCode::kInvalidArgument);
}

TEST(GraspGenerator, BadOptionsAndIndicesAreErrors) {
  GraspSetOptions o = small_grasp_options(1);
  o.objects = 0;
  EXPECT_EQ(GraspEpisodeGenerator::create(o).error().code(), ErrorCode::kInvalidArgument);
  auto gen = make(small_grasp_options(1));
  GraspEpisode e;
  EXPECT_EQ(gen->generate(12, e).error().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(gen->generate(-1, e).error().code(), ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace tlvlink::sim

namespace tlvlink::sim {
namespace {

TEST(GraspGenerator, LivePathFramesAreTheRenderedFramesThroughTheSensorsLivePath) {
  // Mixed profiles: each object's frames go through its own sensor's path (the Mini's MJPEG,
  // DIGIT's YUYV); labels, states and vision are those of the default set.
  GraspSetOptions plain = small_grasp_options(11);
  plain.sensor = "gelsight-mini,digit";
  plain.objects = 6;
  plain.grasps_per_object = 1;
  GraspSetOptions live = plain;
  live.live_path = true;
  auto g = make(live), p = make(plain);
  ASSERT_NE(g, nullptr);
  ASSERT_NE(p, nullptr);
  std::set<std::string> sensors;
  GraspEpisode a, b;
  for (int64_t i = 0; i < live.objects; ++i) {
    ASSERT_TRUE(g->generate(i, a).ok());
    ASSERT_TRUE(p->generate(i, b).ok());
    sensors.insert(a.sensor);
    auto path = LivePath::create(sensor_profile(a.sensor).value());
    ASSERT_TRUE(path.ok());
    EXPECT_EQ(a.is_gripping, b.is_gripping);
    for (int f = 0; f < kFingers; ++f) {
      for (int m = 0; m < kMoments; ++m) {
        std::vector<uint8_t> expected = b.frames[f][m].rgb;
        ASSERT_TRUE((*path)->apply(expected).ok());
        EXPECT_EQ(a.frames[f][m].rgb, expected) << "episode " << i << " finger " << f;
        EXPECT_NE(a.frames[f][m].rgb, b.frames[f][m].rgb);
        EXPECT_EQ(a.states[f][m].force_n, b.states[f][m].force_n);
      }
      EXPECT_EQ(a.vision[f].rgb, b.vision[f].rgb);
    }
  }
  EXPECT_EQ(sensors.size(), 2u);
}

TEST(GraspGenerator, LivePathFractionSendsSomeObjectsThroughTheLivePathAndLeavesTheRest) {
  GraspSetOptions plain = small_grasp_options(13);
  plain.objects = 8;
  plain.grasps_per_object = 2;
  GraspSetOptions mixed = plain, live = plain;
  mixed.live_path_fraction = 0.5;
  live.live_path = true;
  auto g = make(mixed), p = make(plain), l = make(live);
  ASSERT_NE(g, nullptr);
  ASSERT_NE(p, nullptr);
  ASSERT_NE(l, nullptr);
  int live_objects = 0;
  GraspEpisode a, reference;
  for (int64_t object = 0; object < plain.objects; ++object) {
    bool took[2];
    for (int64_t k = 0; k < 2; ++k) {
      const int64_t i = object * 2 + k;
      ASSERT_TRUE(g->generate(i, a).ok());
      took[k] = a.live_path;
      // Each episode is exactly the all-live or the no-live set's: same labels, same frames.
      // Only the set it claims to come from is rendered (the episodes dominate this test's time).
      ASSERT_TRUE((a.live_path ? l : p)->generate(i, reference).ok());
      EXPECT_EQ(reference.live_path, a.live_path) << "episode " << i;
      EXPECT_EQ(a.frames[1][1].rgb, reference.frames[1][1].rgb) << "episode " << i;
      EXPECT_EQ(a.is_gripping, reference.is_gripping) << "episode " << i;
    }
    EXPECT_EQ(took[0], took[1]) << "object " << object;  // drawn per object
    live_objects += took[0] ? 1 : 0;
  }
  EXPECT_GT(live_objects, 0);
  EXPECT_LT(live_objects, plain.objects);
  mixed.live_path_fraction = -0.1;
  EXPECT_EQ(GraspEpisodeGenerator::create(mixed).error().code(), ErrorCode::kInvalidArgument);
  live.live_path_fraction = 0.5;  // every frame, or a share: not both
  EXPECT_EQ(GraspEpisodeGenerator::create(live).error().code(), ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace tlvlink::sim

namespace tlvlink::sim {
namespace {

TEST(GraspGenerator, SuccessGivenClassWeightsMixesTheClassOracles) {
  GraspVariables v;
  v.grip_force_n = 18;
  v.contact_area_mm2[0] = v.contact_area_mm2[1] = 150;
  v.finger_in_contact[0] = v.finger_in_contact[1] = true;
  std::array<double, kMaterialClassCount> a{}, b{}, mix{};
  a[3] = 1;
  b[9] = 1;
  mix[3] = 0.25;
  mix[9] = 0.75;
  const std::vector<GraspVariables> vs = {v, v, v};
  const std::vector<std::array<double, kMaterialClassCount>> ws = {a, b, mix};
  auto p = grasp_success_given_class_weights(vs, ws, 1);
  ASSERT_TRUE(p.ok()) << p.error().message();
  EXPECT_NEAR((*p)[2], 0.25 * (*p)[0] + 0.75 * (*p)[1], 1e-12);
  for (const double x : *p) EXPECT_TRUE(x >= 0 && x <= 1);
  // A missing finger fails whatever the material.
  GraspVariables miss = v;
  miss.finger_in_contact[1] = false;
  const std::vector<GraspVariables> ms = {miss};
  const std::vector<std::array<double, kMaterialClassCount>> wa = {a};
  EXPECT_EQ(grasp_success_given_class_weights(ms, wa, 1).value()[0], 0.0);
  // Weights that are not a distribution, and a length mismatch, are errors.
  std::array<double, kMaterialClassCount> bad = a;
  bad[9] = 0.5;
  const std::vector<std::array<double, kMaterialClassCount>> wbad = {bad};
  const auto e = grasp_success_given_class_weights(ms, wbad, 1);
  ASSERT_FALSE(e.ok());
  EXPECT_NE(std::string(e.error().message()).find("sum to"), std::string::npos);
  EXPECT_FALSE(grasp_success_given_class_weights(vs, wa, 1).ok());
}

}  // namespace
}  // namespace tlvlink::sim
