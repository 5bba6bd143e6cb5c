// Domain randomization over sensor instances: validation, instance seeds, sessions on one
// sensor and different sensors between sessions, independent fingers, the bounded Renderer
// cache and what building a Renderer costs.

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>

#include "gen/rng.h"
#include "gen/sensor_instances.h"
#include "support/random.h"
#include "tlvlink/sim/generate.h"

namespace tlvlink::sim {
namespace {

// Instance backgrounds differ by their illumination polynomial, white balance (+-3 %) and
// exposure (+-5 %): several DN per pixel on a ~125 DN background. Noise (sigma 3 DN) alone
// moves a pixel by ~2.4 DN on average, so a 2 DN gap in mean |difference| between two
// backgrounds is far outside what one sensor shows.
constexpr double kMinBackgroundGapDn = 2.0;

std::vector<std::unique_ptr<Renderer>> instance_renderers(uint64_t seed, int32_t n) {
  std::vector<std::unique_ptr<Renderer>> r;
  const SensorProfile p = sensor_profile("gelsight-mini").value();
  for (int32_t k = 0; k < n; ++k)
    r.push_back(Renderer::create(p, sensor_instance_seed(seed, k)).value());
  return r;
}

double mean_abs_diff(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  if (a.size() != b.size() || a.empty()) return 255;
  double sum = 0;
  for (size_t i = 0; i < a.size(); ++i) sum += std::abs(int{a[i]} - int{b[i]});
  return sum / static_cast<double>(a.size());
}

// The instance whose no-contact background is closest to `rgb`.
int32_t closest_instance(const std::vector<uint8_t>& rgb,
                         const std::vector<std::unique_ptr<Renderer>>& renderers) {
  int32_t best = -1;
  double best_d = 1e9;
  for (size_t k = 0; k < renderers.size(); ++k) {
    const double d = mean_abs_diff(rgb, renderers[k]->background());
    if (d < best_d) best_d = d, best = static_cast<int32_t>(k);
  }
  return best;
}

TouchSetOptions touch_options(uint64_t seed, int32_t instances) {
  TouchSetOptions o;
  o.sessions = 10;
  o.frames_per_session = 3;
  o.vision_height = 24;
  o.vision_width = 32;
  o.seed = seed;
  o.sensor_instances = instances;
  return o;
}

TEST(SensorInstances, BadCountsAreErrorsNamingTheField) {
  for (int32_t n : {0, -3, kMaxSensorInstances + 1}) {
    TouchSetOptions t = touch_options(1, n);
    auto tg = TouchSampleGenerator::create(t);
    ASSERT_FALSE(tg.ok()) << n;
    EXPECT_EQ(tg.error().code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(tg.error().message()).find("sensor_instances"), std::string::npos)
        << tg.error().message();
    GraspSetOptions g;
    g.sensor_instances = n;
    auto gg = GraspEpisodeGenerator::create(g);
    ASSERT_FALSE(gg.ok()) << n;
    EXPECT_NE(std::string(gg.error().message()).find("sensor_instances"), std::string::npos)
        << gg.error().message();
  }
  EXPECT_TRUE(TouchSampleGenerator::create(touch_options(1, kMaxSensorInstances)).ok());
}

TEST(SensorInstances, InstanceZeroKeepsTheSingleSensorSeed) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  EXPECT_EQ(sensor_instance_seed(seed, 0),
            internal::derive_seed(seed, {internal::tag(internal::Stream::kSensor)}));
  std::set<uint64_t> seeds;
  for (int32_t k = 0; k < 1000; ++k) seeds.insert(sensor_instance_seed(seed, k));
  EXPECT_EQ(seeds.size(), 1000u) << "every instance is another sensor";
}

TEST(SensorInstances, NoContactColourDiffersBetweenInstances) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  constexpr int32_t kN = 6;
  const auto renderers = instance_renderers(seed, kN);
  std::vector<std::array<double, 3>> mean(kN);
  for (int32_t k = 0; k < kN; ++k) {
    const auto& bg = renderers[static_cast<size_t>(k)]->background();
    std::array<double, 3> m{};
    for (size_t i = 0; i < bg.size(); ++i) m[i % 3] += bg[i];
    for (double& c : m) c /= static_cast<double>(bg.size() / 3);
    mean[static_cast<size_t>(k)] = m;
    std::printf("instance %d: no-contact mean RGB %.1f %.1f %.1f\n", k, m[0], m[1], m[2]);
  }
  for (int32_t a = 0; a < kN; ++a) {
    for (int32_t b = a + 1; b < kN; ++b) {
      const auto& ma = mean[static_cast<size_t>(a)];
      const auto& mb = mean[static_cast<size_t>(b)];
      EXPECT_GT(
          std::max({std::fabs(ma[0] - mb[0]), std::fabs(ma[1] - mb[1]), std::fabs(ma[2] - mb[2])}),
          0.1)
          << "instances " << a << ", " << b << ": mean colours";
      EXPECT_GT(mean_abs_diff(renderers[static_cast<size_t>(a)]->background(),
                              renderers[static_cast<size_t>(b)]->background()),
                kMinBackgroundGapDn)
          << "instances " << a << ", " << b << ": backgrounds";
    }
  }
}

TEST(SensorInstances, TouchSessionsStayOnOneSensorAndSessionsDiffer) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  constexpr int32_t kN = 5;
  auto many = TouchSampleGenerator::create(touch_options(seed, kN)).value();
  auto one = TouchSampleGenerator::create(touch_options(seed, 1)).value();
  const auto renderers = instance_renderers(seed, kN);
  std::set<int32_t> used;
  TouchSample s, single;
  for (int64_t i = 0; i < many->size(); ++i) {
    SCOPED_TRACE("sample " + std::to_string(i));
    ASSERT_TRUE(many->generate(i, s).ok());
    ASSERT_TRUE(one->generate(i, single).ok());
    const int64_t session = i / 3;
    EXPECT_EQ(s.sensor_instance, internal::touch_session_instance(seed, session, kN))
        << "every frame of a session on the session's sensor";
    ASSERT_GE(s.sensor_instance, 0);
    ASSERT_LT(s.sensor_instance, kN);
    used.insert(s.sensor_instance);
    EXPECT_EQ(closest_instance(s.touch.rgb, renderers), s.sensor_instance)
        << "the frame shows its own sensor's background";
    // Only the sensor changes: the object, press, vision and descriptions stay.
    EXPECT_EQ(s.vision.rgb, single.vision.rgb);
    EXPECT_EQ(s.sentence_desc, single.sentence_desc);
    EXPECT_EQ(s.material.modulus_pa, single.material.modulus_pa);
    EXPECT_EQ(single.sensor_instance, 0);
    if (s.sensor_instance == 0)
      EXPECT_EQ(s.touch.rgb, single.touch.rgb) << "instance 0 is the single-instance sensor";
    else
      EXPECT_NE(s.touch.rgb, single.touch.rgb);
  }
  EXPECT_GE(used.size(), 3u) << "10 sessions on 5 sensors use several of them";
}

TEST(SensorInstances, GraspFingersDrawIndependentInstances) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  // The draw itself, over many episodes: about 1/N of them put both fingers on one sensor,
  // and every instance is used about equally (binomial bounds at ~5 sigma).
  constexpr int32_t kN = 4;
  constexpr int64_t kEpisodes = 4000;
  int64_t same = 0;
  std::map<int32_t, int64_t> count;
  for (int64_t e = 0; e < kEpisodes; ++e) {
    const int32_t a = internal::grasp_finger_instance(seed, e, 0, kN);
    const int32_t b = internal::grasp_finger_instance(seed, e, 1, kN);
    same += a == b;
    ++count[a];
    ++count[b];
  }
  EXPECT_NEAR(static_cast<double>(same) / kEpisodes, 1.0 / kN, 0.035);
  ASSERT_EQ(count.size(), static_cast<size_t>(kN));
  for (const auto& [k, c] : count)
    EXPECT_NEAR(static_cast<double>(c) / (2 * kEpisodes), 0.25, 0.025) << k;

  // Rendered: each finger's no-contact "before" frame shows its own sensor.
  GraspSetOptions o;
  o.objects = 3;
  o.grasps_per_object = 2;
  o.vision_height = 24;
  o.vision_width = 32;
  o.seed = seed;
  o.markers = false;  // backgrounds without the marker grid
  o.sensor_instances = kN;
  auto gen = GraspEpisodeGenerator::create(o).value();
  const auto renderers = instance_renderers(seed, kN);
  GraspEpisode ep;
  for (int64_t i = 0; i < gen->size(); ++i) {
    ASSERT_TRUE(gen->generate(i, ep).ok());
    for (int32_t f = 0; f < kFingers; ++f) {
      EXPECT_EQ(ep.sensor_instance[f], internal::grasp_finger_instance(seed, i, f, kN));
      EXPECT_EQ(closest_instance(ep.frames[f][static_cast<int>(Moment::kBefore)].rgb, renderers),
                ep.sensor_instance[f])
          << "episode " << i << " finger " << f;
    }
  }
}

TEST(SensorInstances, RendererCacheKeepsTwoAndSaysWhatABuildCosts) {
  const SensorProfile p = sensor_profile("gelsight-mini").value();
  auto cache = internal::RendererCache::create(p, 3, 64).value();
  EXPECT_EQ(cache->builds(), 1) << "instance 0 is built at creation";
  ASSERT_TRUE(cache->get(0).ok());
  ASSERT_TRUE(cache->get(1).ok());
  ASSERT_TRUE(cache->get(0).ok());
  EXPECT_EQ(cache->builds(), 2) << "both fingers of an episode stay";
  ASSERT_TRUE(cache->get(2).ok());  // evicts 1, the least recently used
  ASSERT_TRUE(cache->get(0).ok());
  EXPECT_EQ(cache->builds(), 3);
  ASSERT_TRUE(cache->get(1).ok());
  EXPECT_EQ(cache->builds(), 4);
  EXPECT_EQ(cache->get(64).error().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(cache->get(-1).error().code(), ErrorCode::kInvalidArgument);
  EXPECT_FALSE(internal::RendererCache::create(p, 3, 0).ok());

  constexpr int32_t kBuilds = 20;
  const auto t0 = std::chrono::steady_clock::now();
  for (int32_t k = 10; k < 10 + kBuilds; ++k) ASSERT_TRUE(cache->get(k).ok());
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("Renderer build for a new sensor instance (gelsight-mini 240x320): %.2f ms\n",
              ms / kBuilds);
}

}  // namespace
}  // namespace tlvlink::sim
