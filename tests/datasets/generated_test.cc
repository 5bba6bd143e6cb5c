// The simulator's generators through the writers and back through the loaders, and the
// CLI's ordered parallel generation giving the same bytes for any thread count.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <tuple>

#include "datasets/samples.h"
#include "tlvlink/datasets/datasets.h"
#include "tlvlink/sim/generate.h"
#include "tlvlink/sim/sets.h"

namespace tlvlink::datasets {
namespace {

using testing::TempDir;

sim::TouchSetOptions small_touch_set() {
  sim::TouchSetOptions o;
  o.sessions = 3;
  o.frames_per_session = 2;
  o.vision_height = 48;
  o.vision_width = 64;
  o.seed = 11;
  return o;
}

Status write_touch(const std::string& dir, const sim::TouchSetOptions& gen, int threads, bool tag) {
  // The simulator's set writer: one generator per thread through the batch generator.
  sim::TouchSetJob job;
  job.generator = gen;
  job.format = tag ? sim::TouchSetFormat::kTouchAndGo : sim::TouchSetFormat::kTouch100k;
  job.writer.test_fraction = 1.0 / 3.0;
  job.dir = dir;
  job.threads = threads;
  job.progress_label = "test";
  return sim::write_touch_set(job).status();
}

std::string file_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Generated, TouchSetsLoadBackInBothFormats) {
  TempDir tmp;
  const auto gen = small_touch_set();
  ASSERT_TRUE(write_touch(tmp / "t100k", gen, 1, false).ok());
  ASSERT_TRUE(write_touch(tmp / "tag", gen, 1, true).ok());
  auto generator = sim::TouchSampleGenerator::create(gen);
  ASSERT_TRUE(generator.ok());
  std::vector<sim::TouchSample> want(6);
  for (int64_t i = 0; i < 6; ++i)
    ASSERT_TRUE((*generator)->generate(i, want[static_cast<size_t>(i)]).ok());

  auto t100k = open_touch100k(tmp / "t100k", {});
  ASSERT_TRUE(t100k.ok());
  sim::TouchSample got;
  for (const auto& w : want) {
    auto more = (*t100k)->next(got);
    ASSERT_TRUE(more.ok() && more.value());
    EXPECT_EQ(got.sentence_desc, w.sentence_desc);
    EXPECT_EQ(got.phrases, w.phrases);
    EXPECT_EQ(got.session, w.session);
    EXPECT_EQ(got.material.class_id, w.material.class_id);
    EXPECT_EQ(got.touch.width, w.touch.width);
    EXPECT_EQ(got.vision.height, 48);
  }
  EXPECT_EQ((*t100k)->report().problem_count(), 0) << (*t100k)->report().summary();

  TagLoaderOptions o;
  o.split = Split::kAll;
  auto tag = open_touch_and_go(tmp / "tag", o);
  ASSERT_TRUE(tag.ok());
  int n = 0;
  while ((*tag)->next(got).value()) ++n;
  EXPECT_EQ(n, 6);
  EXPECT_EQ((*tag)->report().problem_count(), 0) << (*tag)->report().summary();
  auto stats = dataset_stats(tmp / "t100k");
  ASSERT_TRUE(stats.ok());
  EXPECT_EQ(stats->samples, 6);
  EXPECT_GT(stats->sentence_mean_words, 0.0);
}

// Every regular file under `a` has the same bytes under `b`; returns how many were compared.
int expect_same_files(const std::filesystem::path& a, const std::filesystem::path& b) {
  int files = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(a)) {
    if (!e.is_regular_file()) continue;
    const auto rel = std::filesystem::relative(e.path(), a);
    EXPECT_EQ(file_bytes(e.path()), file_bytes(b / rel)) << rel;
    ++files;
  }
  return files;
}

TEST(Generated, OutputDoesNotDependOnTheThreadCount) {
  TempDir tmp;
  const auto gen = small_touch_set();
  ASSERT_TRUE(write_touch(tmp / "one", gen, 1, false).ok());
  ASSERT_TRUE(write_touch(tmp / "three", gen, 3, false).ok());
  // images, data_list.json, sidecar, tlvlink_sim.json
  EXPECT_EQ(expect_same_files(tmp / "one", tmp / "three"), 6 * 2 + 3);
}

// With several sensor instances a worker switches Renderers between sessions: the bytes must
// still depend only on (seed, index), and the instance is recorded in the sidecar and options.
TEST(Generated, SensorInstancesDoNotDependOnTheThreadCountAndAreRecorded) {
  TempDir tmp;
  auto gen = small_touch_set();
  gen.sessions = 6;
  gen.sensor_instances = 4;
  ASSERT_TRUE(write_touch(tmp / "one", gen, 1, false).ok());
  ASSERT_TRUE(write_touch(tmp / "three", gen, 3, false).ok());
  EXPECT_EQ(expect_same_files(tmp / "one", tmp / "three"), 12 * 2 + 3);

  const auto prov = nlohmann::json::parse(file_bytes(tmp / "one/tlvlink_sim.json"));
  EXPECT_EQ(prov["generator"]["sensor_instances"], 4);
  auto generator = sim::TouchSampleGenerator::create(gen);
  ASSERT_TRUE(generator.ok());
  auto loader = open_touch100k(tmp / "one", {});
  ASSERT_TRUE(loader.ok());
  sim::TouchSample want, got;
  std::set<int32_t> used;
  for (int64_t i = 0; i < (*generator)->size(); ++i) {
    ASSERT_TRUE((*generator)->generate(i, want).ok());
    auto more = (*loader)->next(got);
    ASSERT_TRUE(more.ok() && more.value());
    EXPECT_EQ(got.sensor_instance, want.sensor_instance) << "sample " << i;
    used.insert(want.sensor_instance);
  }
  EXPECT_GE(used.size(), 2u) << "6 sessions on 4 sensors";
  EXPECT_EQ((*loader)->report().problem_count(), 0) << (*loader)->report().summary();
}

TEST(Generated, GraspEpisodesLoadBackFromHdf5AndRepacked) {
  TempDir tmp;
  sim::GraspSetOptions gen;
  gen.objects = 3;
  gen.grasps_per_object = 2;
  gen.vision_height = 24;
  gen.vision_width = 32;
  gen.seed = 5;
  gen.sensor_instances = 3;
  gen.sensor = "gelsight-mini,digit";  // a mixed set: landscape and portrait frames in one set
  auto generator = sim::GraspEpisodeGenerator::create(gen);
  ASSERT_TRUE(generator.ok()) << generator.error().message();
  FeelWriterOptions wo;
  wo.generator_json = sim::grasp_set_options_json(gen);
  wo.camera_jpeg_quality = 95;
  auto h5 = create_feel_writer(tmp / "h5", wo);
  auto repacked = create_feel_repacked_writer(tmp / "repacked", wo);
  ASSERT_TRUE(h5.ok() && repacked.ok());
  std::vector<sim::GraspEpisode> want(6);
  for (int64_t i = 0; i < 6; ++i) {
    auto& e = want[static_cast<size_t>(i)];
    ASSERT_TRUE((*generator)->generate(i, e).ok());
    ASSERT_TRUE((*h5)->write(e).ok());
    ASSERT_TRUE((*repacked)->write(e).ok());
  }
  ASSERT_TRUE((*h5)->finish().ok());
  ASSERT_TRUE((*repacked)->finish().ok());

  auto loader = open_feel(tmp / "h5", {});
  ASSERT_TRUE(loader.ok());
  sim::GraspEpisode got;
  for (const auto& w : want) {
    auto more = (*loader)->next(got);
    ASSERT_TRUE(more.ok() && more.value());
    EXPECT_EQ(got.object_name, w.object_name);
    EXPECT_EQ(got.is_gripping, w.is_gripping);
    EXPECT_DOUBLE_EQ(got.variables.mass_kg, w.variables.mass_kg);
    EXPECT_EQ(got.sensor_instance[0], w.sensor_instance[0]);  // from the tlvlink_sim attribute
    EXPECT_EQ(got.sensor_instance[1], w.sensor_instance[1]);
    EXPECT_EQ(got.sensor, w.sensor);
    EXPECT_FALSE(got.live_path);
    EXPECT_EQ(got.frames[1][1].width, w.frames[1][1].width);
    EXPECT_EQ(got.frames[1][1].height, w.frames[1][1].height);
    EXPECT_EQ(got.vision[2].width, 32);
  }
  EXPECT_EQ((*loader)->report().problem_count(), 0) << (*loader)->report().summary();
  FeelLoaderOptions all;
  auto rl = open_feel_repacked(tmp / "repacked", all);
  ASSERT_TRUE(rl.ok());
  // The repacked loader gives the train split first: compare as sets of (episode, instances).
  using Key = std::tuple<std::string, double, int32_t, int32_t, std::string>;
  std::multiset<Key> wrote, loaded;
  std::set<std::string> profiles;
  for (const auto& w : want) {
    wrote.emplace(w.object_name, w.variables.com_offset_mm, w.sensor_instance[0],
                  w.sensor_instance[1], w.sensor);
    profiles.insert(w.sensor);
  }
  EXPECT_EQ(profiles.size(), 2u) << "seed 5's three objects draw both profiles";
  int n = 0;
  while ((*rl)->next(got).value()) {
    ++n;
    loaded.emplace(got.object_name, got.variables.com_offset_mm, got.sensor_instance[0],
                   got.sensor_instance[1], got.sensor);  // instances and profile from the sidecar
  }
  EXPECT_EQ(loaded, wrote);
  EXPECT_EQ(n, 6);
  EXPECT_EQ((*rl)->report().problem_count(), 0) << (*rl)->report().summary();
}

// A live-path set (sim feel --live-path): the stored GelSight frames are the generator's, with no
// second camera round trip on top (camera_jpeg_quality then reaches the vision frames only), and
// the provenance says how they were made.
TEST(Generated, LivePathGraspSetStoresTheLivePathFramesAsTheyAre) {
  TempDir tmp;
  sim::GraspSetJob job;
  job.generator.objects = 2;
  job.generator.grasps_per_object = 1;
  job.generator.vision_height = 24;
  job.generator.vision_width = 32;
  job.generator.seed = 3;
  job.generator.live_path = true;
  job.writer.camera_jpeg_quality = 95;
  job.dir = tmp / "live";
  auto written = sim::write_grasp_set(job);
  ASSERT_TRUE(written.ok()) << written.error().message();
  auto generator = sim::GraspEpisodeGenerator::create(job.generator);
  ASSERT_TRUE(generator.ok());
  auto loader = open_feel(tmp / "live", {});
  ASSERT_TRUE(loader.ok());
  sim::GraspEpisode want, got;
  for (int64_t i = 0; i < 2; ++i) {
    ASSERT_TRUE((*generator)->generate(i, want).ok());
    auto more = (*loader)->next(got);
    ASSERT_TRUE(more.ok() && more.value());
    EXPECT_EQ(got.frames[0][1].rgb, want.frames[0][1].rgb) << "episode " << i;
    EXPECT_EQ(got.frames[1][0].rgb, want.frames[1][0].rgb) << "episode " << i;
    EXPECT_NE(got.vision[1].rgb, want.vision[1].rgb) << "the vision frames keep their round trip";
    EXPECT_TRUE(got.live_path) << "the sidecar says which path the episode took";
  }
  std::ifstream in(tmp / "live/tlvlink_sim.json");
  const auto provenance = nlohmann::json::parse(in);
  EXPECT_EQ(provenance["generator"]["live_path"], true);
}

}  // namespace
}  // namespace tlvlink::datasets
