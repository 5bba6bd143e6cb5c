// The simulated sensor instance of each sample / finger through the sidecars: written, read
// back, 0 from sidecars written before the field existed, -1 without simulator metadata, and a
// malformed value counted as a sidecar problem.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "datasets/samples.h"
#include "tlvlink/datasets/feel.h"
#include "tlvlink/datasets/touch100k.h"
#include "tlvlink/datasets/touch_and_go.h"

namespace tlvlink::datasets {
namespace {

using testing::TempDir;

std::vector<datasets::TouchSample> touch_set_on_instances() {
  auto samples = testing::touch_set(3, 2);  // sessions of two frames
  for (size_t i = 0; i < samples.size(); ++i)
    samples[i].sensor_instance = 2 + 3 * static_cast<int32_t>(i / 2);  // 2, 5, 8
  return samples;
}

void write_touch100k(const std::string& dir, const std::vector<datasets::TouchSample>& samples,
                     bool sidecar = true) {
  WriterOptions o;
  o.sidecar = sidecar;
  auto writer = create_touch100k_writer(dir, o);
  ASSERT_TRUE(writer.ok()) << writer.error().message();
  for (const auto& s : samples) ASSERT_TRUE((*writer)->write(s).ok());
  ASSERT_TRUE((*writer)->finish().ok());
}

std::vector<int32_t> touch100k_instances(const std::string& dir, LoadReport* report = nullptr) {
  Touch100kLoaderOptions o;
  o.load_images = false;
  auto loader = open_touch100k(dir, o);
  EXPECT_TRUE(loader.ok());
  std::vector<int32_t> out;
  datasets::TouchSample s;
  s.sensor_instance = 99;  // a reused sample must not keep an old value
  while (loader.ok() && (*loader)->next(s).value()) out.push_back(s.sensor_instance);
  if (loader.ok() && report) *report = (*loader)->report();
  return out;
}

// Rewrites every line of a JSON-lines file with `edit`.
template <typename Edit>
void edit_lines(const std::string& path, Edit edit) {
  auto lines = testing::read_lines(path);
  for (std::string& line : lines) {
    auto j = nlohmann::ordered_json::parse(line);
    edit(j);
    line = j.dump();
  }
  testing::write_lines(path, lines);
}

TEST(SensorInstanceMeta, TouchInstancesRoundTripInBothFormats) {
  TempDir tmp;
  const auto samples = touch_set_on_instances();
  write_touch100k(tmp / "t100k", samples);
  EXPECT_EQ(touch100k_instances(tmp / "t100k"), (std::vector<int32_t>{2, 2, 5, 5, 8, 8}));

  auto writer = create_tag_writer(tmp / "tag", {});
  ASSERT_TRUE(writer.ok());
  for (const auto& s : samples) ASSERT_TRUE((*writer)->write(s).ok());
  ASSERT_TRUE((*writer)->finish().ok());
  TagLoaderOptions o;
  o.split = Split::kAll;
  o.load_images = false;
  auto tag = open_touch_and_go(tmp / "tag", o);
  ASSERT_TRUE(tag.ok());
  std::map<std::string, int32_t> want;
  for (const auto& s : samples) want[s.session] = s.sensor_instance;
  datasets::TouchSample s;
  int n = 0;
  while ((*tag)->next(s).value()) {
    EXPECT_EQ(s.sensor_instance, want.at(s.session)) << s.session;
    ++n;
  }
  EXPECT_EQ(n, 6);
  EXPECT_EQ((*tag)->report().problem_count(), 0) << (*tag)->report().summary();
}

TEST(SensorInstanceMeta, OldSidecarsMeanInstanceZeroAndNoSidecarUnknown) {
  TempDir tmp;
  write_touch100k(tmp / "old", touch_set_on_instances());
  edit_lines(tmp / ("old/" + std::string(kTouch100kSidecar)),
             [](auto& j) { j.erase("sensor_instance"); });
  LoadReport report;
  EXPECT_EQ(touch100k_instances(tmp / "old", &report), std::vector<int32_t>(6, 0));
  EXPECT_EQ(report.problem_count(), 0) << report.summary();

  write_touch100k(tmp / "bare", touch_set_on_instances(), /*sidecar=*/false);
  EXPECT_EQ(touch100k_instances(tmp / "bare"), std::vector<int32_t>(6, -1));
}

TEST(SensorInstanceMeta, MalformedInstanceIsASidecarProblem) {
  TempDir tmp;
  write_touch100k(tmp.path(), touch_set_on_instances());
  int line = 0;
  edit_lines(tmp / kTouch100kSidecar, [&line](auto& j) {
    if (line == 1) j["sensor_instance"] = "two";
    if (line == 3) j["sensor_instance"] = -4;
    ++line;
  });
  LoadReport report;
  const auto got = touch100k_instances(tmp.path(), &report);
  // The sidecar carries the labels: a bad line drops its sample (issue 12), named by file:line.
  EXPECT_EQ(got.size(), 4u);
  EXPECT_EQ(report.malformed_lines(), 2) << report.summary();
  ASSERT_EQ(report.problems().size(), 2u);
  EXPECT_EQ(report.problems()[0].line, 2);
  EXPECT_EQ(report.problems()[1].line, 4);
  EXPECT_NE(report.problems()[0].path.find(kTouch100kSidecar), std::string::npos);
}

TEST(SensorInstanceMeta, GraspFingerInstancesRoundTripAndOldSidecars) {
  TempDir tmp;
  std::vector<datasets::GraspEpisode> episodes;
  for (int32_t g = 0; g < 3; ++g) {
    episodes.push_back(testing::grasp_episode(0, g));
    episodes.back().sensor_instance[0] = g;
    episodes.back().sensor_instance[1] = 10 + g;
  }
  FeelWriterOptions wo;
  wo.test_fraction = 0;
  auto writer = create_feel_repacked_writer(tmp.path(), wo);
  ASSERT_TRUE(writer.ok()) << writer.error().message();
  for (const auto& e : episodes) ASSERT_TRUE((*writer)->write(e).ok());
  ASSERT_TRUE((*writer)->finish().ok());

  auto read = [&tmp] {
    FeelLoaderOptions o;
    o.load_images = false;
    auto loader = open_feel_repacked(tmp.path(), o);
    EXPECT_TRUE(loader.ok());
    std::vector<std::pair<int32_t, int32_t>> out;
    datasets::GraspEpisode e;
    while (loader.ok() && (*loader)->next(e).value())
      out.emplace_back(e.sensor_instance[0], e.sensor_instance[1]);
    if (loader.ok()) {
      EXPECT_EQ((*loader)->report().problem_count(), 0) << (*loader)->report().summary();
    }
    return out;
  };
  using Pairs = std::vector<std::pair<int32_t, int32_t>>;
  EXPECT_EQ(read(), (Pairs{{0, 10}, {1, 11}, {2, 12}}));
  edit_lines(tmp / "tlvlink_sim_train.jsonl", [](auto& j) { j.erase("sensor_instance"); });
  EXPECT_EQ(read(), (Pairs{{0, 0}, {0, 0}, {0, 0}}));
}

}  // namespace
}  // namespace tlvlink::datasets
