// Feel HDF5 writer -> loader: the documented keys, exact frames, hidden variables from the
// tlvlink_sim attribute, object-disjoint splits, rotation, broken files and records.

#include "tlvlink/datasets/feel.h"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "datasets/samples.h"

namespace tlvlink::datasets {
namespace {

using testing::TempDir;

std::vector<datasets::GraspEpisode> episodes(int32_t objects, int32_t grasps) {
  std::vector<datasets::GraspEpisode> out;
  for (int32_t o = 0; o < objects; ++o)
    for (int32_t g = 0; g < grasps; ++g) out.push_back(testing::grasp_episode(o, g));
  return out;
}

void write_h5(const std::string& dir, const std::vector<datasets::GraspEpisode>& eps,
              FeelWriterOptions o = {}) {
  o.records_per_file = 5;
  o.test_fraction = 0.25;
  auto writer = create_feel_writer(dir, o);
  ASSERT_TRUE(writer.ok()) << writer.error().message();
  for (const auto& e : eps) ASSERT_TRUE((*writer)->write(e).ok());
  ASSERT_TRUE((*writer)->finish().ok());
  EXPECT_EQ((*writer)->summary().items, static_cast<int64_t>(eps.size()));
}

struct LoadedFeel {
  std::vector<datasets::GraspEpisode> episodes;
  std::vector<std::string> keys;
  LoadReport report;
};

LoadedFeel load_feel(const std::string& path, FeelLoaderOptions o = {}) {
  LoadedFeel out;
  auto loader = open_feel(path, o);
  EXPECT_TRUE(loader.ok()) << loader.error().message();
  if (!loader.ok()) return out;
  datasets::GraspEpisode e;
  for (;;) {
    auto more = (*loader)->next(e);
    EXPECT_TRUE(more.ok());
    if (!more.ok() || !more.value()) break;
    out.episodes.push_back(e);
    out.keys.push_back((*loader)->key());
  }
  out.report = (*loader)->report();
  return out;
}

TEST(FeelHdf5, RoundTripIsExact) {
  TempDir tmp;
  const auto eps = episodes(4, 3);
  write_h5(tmp.path(), eps);
  for (const char* f :
       {"calandra_corl2017_000.h5", "calandra_corl2017_001.h5", "calandra_corl2017_002.h5"})
    EXPECT_TRUE(std::filesystem::exists(tmp / f)) << f;
  EXPECT_FALSE(std::filesystem::exists(tmp / "calandra_corl2017_003.h5"));
  const LoadedFeel l = load_feel(tmp.path());
  ASSERT_EQ(l.episodes.size(), eps.size());
  EXPECT_EQ(l.report.problem_count(), 0) << l.report.summary();
  EXPECT_EQ(l.keys[6], "calandra_corl2017_001.h5:/0001");
  for (size_t i = 0; i < eps.size(); ++i) {
    const auto& a = eps[i];
    const auto& b = l.episodes[i];
    EXPECT_EQ(b.object_name, a.object_name);
    EXPECT_EQ(b.is_gripping, a.is_gripping);
    EXPECT_EQ(b.object_id, a.object_id);
    EXPECT_DOUBLE_EQ(b.variables.mass_kg, a.variables.mass_kg);  // hidden
    EXPECT_DOUBLE_EQ(b.variables.lift_accel_mps2, a.variables.lift_accel_mps2);
    EXPECT_EQ(b.variables.finger_in_contact[1], a.variables.finger_in_contact[1]);
    EXPECT_DOUBLE_EQ(b.states[1][2].force_n, a.states[1][2].force_n);
    for (int f = 0; f < heads::kFingers; ++f)
      for (int m = 0; m < heads::kMoments; ++m) {
        EXPECT_EQ(b.frames[f][m].rgb, a.frames[f][m].rgb);  // deflate is lossless
        EXPECT_EQ(b.frames[f][m].width, a.frames[f][m].width);
      }
    for (int m = 0; m < heads::kMoments; ++m) EXPECT_EQ(b.vision[m].rgb, a.vision[m].rgb);
  }
}

TEST(FeelHdf5, RecordedSplitIsByObject) {
  TempDir tmp;
  write_h5(tmp.path(), episodes(8, 3));
  FeelLoaderOptions o;
  o.split = Split::kTrain;
  std::set<std::string> train;
  const LoadedFeel tr = load_feel(tmp.path(), o);
  for (const auto& e : tr.episodes) train.insert(e.object_name);
  o.split = Split::kTest;
  const LoadedFeel te = load_feel(tmp.path(), o);
  std::set<std::string> test;
  for (const auto& e : te.episodes) test.insert(e.object_name);
  EXPECT_EQ(train.size(), 6u);
  EXPECT_EQ(test.size(), 2u);
  for (const auto& n : test) EXPECT_EQ(train.count(n), 0u) << n;
  EXPECT_EQ(tr.episodes.size() + te.episodes.size(), 24u);
  // Re-split by object hash: deterministic, disjoint.
  o.resplit = HashSplit{0.5, 3};
  const LoadedFeel a = load_feel(tmp.path(), o);
  const LoadedFeel b = load_feel(tmp.path(), o);
  EXPECT_EQ(a.keys, b.keys);
  for (const auto& e : a.episodes) EXPECT_TRUE(hash_split_is_test(e.object_name, *o.resplit));
}

TEST(FeelHdf5, QuarterTurnsAreUndoneByTheLoader) {
  TempDir tmp;
  const auto eps = episodes(1, 2);
  FeelWriterOptions w;
  w.gelsight_quarter_turns = 1;
  write_h5(tmp.path(), eps, w);
  const LoadedFeel stored = load_feel(tmp.path());  // as stored: rotated
  ASSERT_EQ(stored.episodes.size(), 2u);
  EXPECT_EQ(stored.episodes[0].frames[0][0].width, eps[0].frames[0][0].height);
  FeelLoaderOptions o;
  o.gelsight_quarter_turns = 1;
  const LoadedFeel back = load_feel(tmp.path(), o);
  ASSERT_EQ(back.episodes.size(), 2u);
  EXPECT_EQ(back.episodes[1].frames[1][2].rgb, eps[1].frames[1][2].rgb);
  EXPECT_EQ(back.episodes[1].vision[0].rgb, eps[1].vision[0].rgb);  // kinect is not rotated
}

TEST(FeelHdf5, TruncatedAndForeignFilesAreCountedWithAClearReason) {
  TempDir tmp;
  write_h5(tmp.path(), episodes(3, 5));  // 3 files of 5
  const std::string truncated = tmp / "calandra_corl2017_001.h5";
  std::filesystem::resize_file(truncated, std::filesystem::file_size(truncated) / 2);
  const std::string foreign = tmp / "calandra_corl2017_002.h5";
  std::ofstream(foreign, std::ios::trunc) << "not an HDF5 file at all";
  const LoadedFeel l = load_feel(tmp.path());
  EXPECT_EQ(l.episodes.size(), 5u);
  EXPECT_EQ(l.report.corrupt_files(), 2);
  ASSERT_EQ(l.report.problems().size(), 2u);
  EXPECT_EQ(l.report.problems()[0].path, truncated);
  EXPECT_NE(l.report.problems()[0].reason.find("cannot open as HDF5"), std::string::npos)
      << l.report.problems()[0].reason;
  EXPECT_EQ(l.report.problems()[1].path, foreign);
  // One truncated file given on its own: nothing loads, the problem says why.
  const LoadedFeel one = load_feel(truncated);
  EXPECT_TRUE(one.episodes.empty());
  EXPECT_EQ(one.report.corrupt_files(), 1);
  const LoadedFeel absent = load_feel(tmp / "calandra_corl2017_999.h5");
  EXPECT_EQ(absent.report.missing_files(), 1);
  std::filesystem::create_directory(tmp / "empty");
  EXPECT_EQ(open_feel(tmp / "empty", {}).error().code(), ErrorCode::kIo);
}

TEST(FeelHdf5, RecordWithoutADocumentedKeyIsSkipped) {
  TempDir tmp;
  write_h5(tmp.path(), episodes(1, 3));
  const std::string path = tmp / "calandra_corl2017_000.h5";
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  ASSERT_GE(H5Ldelete(file, "0001/gelsightB_during", H5P_DEFAULT), 0);
  H5Fclose(file);
  const LoadedFeel l = load_feel(tmp.path());
  EXPECT_EQ(l.episodes.size(), 2u);
  EXPECT_EQ(l.report.count(ProblemKind::kMalformedRecord), 1);
  ASSERT_EQ(l.report.problems().size(), 1u);
  EXPECT_EQ(l.report.problems()[0].path, path);
  EXPECT_NE(l.report.problems()[0].reason.find("/0001"), std::string::npos);
  EXPECT_NE(l.report.problems()[0].reason.find("gelsightB_during"), std::string::npos);
}

TEST(FeelHdf5, WriterRefusesBadOptions) {
  TempDir tmp;
  FeelWriterOptions o;
  o.records_per_file = 0;
  EXPECT_EQ(create_feel_writer(tmp.path(), o).error().code(), ErrorCode::kInvalidArgument);
  o = {};
  o.deflate_level = 10;
  EXPECT_EQ(create_feel_writer(tmp.path(), o).error().code(), ErrorCode::kInvalidArgument);
  auto writer = create_feel_writer(tmp.path(), {});
  ASSERT_TRUE(writer.ok());
  auto e = testing::grasp_episode(0, 0);
  e.vision[1] = {};
  EXPECT_EQ((*writer)->write(e).error().code(), ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace tlvlink::datasets
