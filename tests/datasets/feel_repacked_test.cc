// TLV-Link's repacked Feel layout: writer -> loader, object-disjoint info files, problems.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <set>

#include "datasets/samples.h"
#include "tlvlink/datasets/feel.h"

namespace tlvlink::datasets {
namespace {

using testing::TempDir;

// q=95 by default for this layout; double compression (camera q=95 first) adds a little.
constexpr double kRepackedJpegMeanTolerance = 3.0;

void write_repacked(const std::string& dir, int32_t objects, int32_t grasps,
                    FeelWriterOptions o = {}) {
  o.jpeg_quality = 95;
  o.test_fraction = 0.2;
  auto writer = create_feel_repacked_writer(dir, o);
  ASSERT_TRUE(writer.ok()) << writer.error().message();
  for (int32_t ob = 0; ob < objects; ++ob)
    for (int32_t g = 0; g < grasps; ++g)
      ASSERT_TRUE((*writer)->write(testing::grasp_episode(ob, g)).ok());
  ASSERT_TRUE((*writer)->finish().ok());
}

std::vector<datasets::GraspEpisode> load_repacked(const std::string& dir, FeelLoaderOptions o,
                                                  LoadReport* report = nullptr) {
  std::vector<datasets::GraspEpisode> out;
  auto loader = open_feel_repacked(dir, o);
  EXPECT_TRUE(loader.ok()) << loader.error().message();
  if (!loader.ok()) return out;
  datasets::GraspEpisode e;
  for (;;) {
    auto more = (*loader)->next(e);
    EXPECT_TRUE(more.ok());
    if (!more.ok() || !more.value()) break;
    out.push_back(e);
  }
  if (report) *report = (*loader)->report();
  return out;
}

TEST(FeelRepacked, RoundTripAndObjectSplit) {
  TempDir tmp;
  FeelWriterOptions w;
  w.camera_jpeg_quality = 95;  // Feel-like double compression
  write_repacked(tmp.path(), 5, 2, w);
  const auto info = testing::read_lines(tmp / "train_info.json");
  ASSERT_EQ(info.size(), 8u);
  const auto first = nlohmann::json::parse(info[0]);
  EXPECT_EQ(first["object"], "object_00");
  EXPECT_EQ(first["touch_dir"], "object_00_000000");
  EXPECT_EQ(first["grasping"], true);
  EXPECT_TRUE(std::filesystem::exists(tmp / "data/object_00_000000/gelsightB_after.jpg"));

  FeelLoaderOptions o;
  o.split = Split::kTrain;
  LoadReport report;
  const auto train = load_repacked(tmp.path(), o, &report);
  EXPECT_EQ(report.problem_count(), 0) << report.summary();
  o.split = Split::kTest;
  const auto test = load_repacked(tmp.path(), o);
  ASSERT_EQ(train.size(), 8u);
  ASSERT_EQ(test.size(), 2u);
  std::set<std::string> train_objects;
  for (const auto& e : train) train_objects.insert(e.object_name);
  for (const auto& e : test) EXPECT_EQ(train_objects.count(e.object_name), 0u);
  const auto want = testing::grasp_episode(0, 1);
  EXPECT_EQ(train[1].object_name, want.object_name);
  EXPECT_EQ(train[1].is_gripping, want.is_gripping);
  EXPECT_DOUBLE_EQ(train[1].variables.com_offset_mm, want.variables.com_offset_mm);
  for (int f = 0; f < heads::kFingers; ++f)
    for (int m = 0; m < heads::kMoments; ++m)
      EXPECT_LE(testing::image_diff(train[1].frames[f][m], want.frames[f][m]).mean,
                kRepackedJpegMeanTolerance);
  EXPECT_TRUE(train[1].vision[0].rgb.empty());
}

TEST(FeelRepacked, ProblemsAreCountedAndLoadingGoesOn) {
  TempDir tmp;
  write_repacked(tmp.path(), 5, 2);
  std::filesystem::remove(tmp / "data/object_01_000003/gelsightA_during.jpg");
  auto info = testing::read_lines(tmp / "train_info.json");
  info.push_back(R"({"object": "object_09", "touch_dir": "object_09_000099", "grasping": "yes"})");
  info.push_back(R"({"object": "object_01", "touch_dir": "object_01_000002", "grasping": 0})");
  testing::write_lines(tmp / "train_info.json", info);
  FeelLoaderOptions o;
  o.split = Split::kTrain;
  LoadReport report;
  const auto train = load_repacked(tmp.path(), o, &report);
  EXPECT_EQ(train.size(), 8u);  // 8 - 1 missing + 1 valid extra line
  EXPECT_EQ(report.missing_files(), 1);
  EXPECT_EQ(report.malformed_lines(), 1);
  EXPECT_EQ(report.count(ProblemKind::kSidecarMismatch), 1);  // the sidecar ends before the index
  bool found_line = false;
  for (const auto& p : report.problems())
    if (p.kind == ProblemKind::kMalformedLine) {
      EXPECT_EQ(p.path, tmp / "train_info.json");
      EXPECT_EQ(p.line, 9);
      found_line = true;
    }
  EXPECT_TRUE(found_line);
  EXPECT_FALSE(train.back().is_gripping);
}

}  // namespace
}  // namespace tlvlink::datasets
