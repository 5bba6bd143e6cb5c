// Touch100k writer -> loader: descriptions, images, sidecar metadata; missing / corrupt files
// and malformed lines are counted with their paths and loading goes on.

#include "tlvlink/datasets/touch100k.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "datasets/samples.h"

namespace tlvlink::datasets {
namespace {

using testing::TempDir;

// Writer default q=90 on the smooth test images: mean error ~1 DN, single pixels a few more.
constexpr double kTouch100kJpegMeanTolerance = 3.0;
constexpr int kJpegMaxTolerance = 40;

void write_touch100k_set(const std::string& dir, const std::vector<datasets::TouchSample>& samples,
                         WriterOptions options = {}) {
  options.generator_json = R"({"seed": 7, "sessions": 3})";
  auto writer = create_touch100k_writer(dir, options);
  ASSERT_TRUE(writer.ok()) << writer.error().message();
  for (const auto& s : samples) ASSERT_TRUE((*writer)->write(s).ok());
  ASSERT_TRUE((*writer)->finish().ok());
  EXPECT_EQ((*writer)->summary().items, static_cast<int64_t>(samples.size()));
}

std::vector<datasets::TouchSample> load_all(const std::string& dir,
                                            LoadReport* report_out = nullptr,
                                            Touch100kLoaderOptions options = {}) {
  auto loader = open_touch100k(dir, options);
  EXPECT_TRUE(loader.ok()) << loader.error().message();
  std::vector<datasets::TouchSample> out;
  if (!loader.ok()) return out;
  datasets::TouchSample s;
  for (;;) {
    auto more = (*loader)->next(s);
    EXPECT_TRUE(more.ok());
    if (!more.ok() || !more.value()) break;
    out.push_back(s);
  }
  if (report_out) *report_out = (*loader)->report();
  return out;
}

TEST(Touch100k, RoundTrip) {
  TempDir tmp;
  const auto samples = testing::touch_set(3, 4);
  write_touch100k_set(tmp.path(), samples);

  // The index is exactly the released format.
  const auto lines = testing::read_lines(tmp / "data_list.json");
  ASSERT_EQ(lines.size(), samples.size());
  const auto first = nlohmann::json::parse(lines[0]);
  EXPECT_EQ(first.size(), 3u);
  EXPECT_EQ(first["img"], "20220101_000000/0000000003.jpg");
  EXPECT_EQ(first["phrase_desc"], "cool, smooth, frame 0");
  EXPECT_TRUE(std::filesystem::exists(tmp / "touch/20220101_000000/0000000003.jpg"));
  EXPECT_TRUE(std::filesystem::exists(tmp / "vision/20220101_000000/0000000003.jpg"));
  const auto prov = nlohmann::json::parse(std::ifstream(tmp / "tlvlink_sim.json"));
  EXPECT_EQ(prov["format"], "touch100k");
  EXPECT_EQ(prov["generator"]["seed"], 7);
  EXPECT_EQ(prov["counts"]["items"], 12);

  LoadReport report;
  const auto loaded = load_all(tmp.path(), &report);
  ASSERT_EQ(loaded.size(), samples.size());
  EXPECT_EQ(report.problem_count(), 0) << report.summary();
  for (size_t i = 0; i < samples.size(); ++i) {
    const auto& a = samples[i];
    const auto& b = loaded[i];
    EXPECT_EQ(b.session, a.session);
    EXPECT_EQ(b.frame_index, a.frame_index);
    EXPECT_EQ(b.sentence_desc, a.sentence_desc);
    EXPECT_EQ(b.phrases, a.phrases);
    EXPECT_EQ(b.object_id, a.object_id);  // from the sidecar
    EXPECT_EQ(b.material.class_id, a.material.class_id);
    EXPECT_EQ(b.material.rough, a.material.rough);
    EXPECT_DOUBLE_EQ(b.material.modulus_pa, a.material.modulus_pa);
    EXPECT_DOUBLE_EQ(b.contact.force_n, a.contact.force_n);
    EXPECT_EQ(b.contact.markers_deviating, a.contact.markers_deviating);
    const auto dt = testing::image_diff(a.touch, b.touch);
    const auto dv = testing::image_diff(a.vision, b.vision);
    EXPECT_LE(dt.mean, kTouch100kJpegMeanTolerance);
    EXPECT_LE(dt.max, kJpegMaxTolerance);
    EXPECT_LE(dv.mean, kTouch100kJpegMeanTolerance);
    EXPECT_LE(dv.max, kJpegMaxTolerance);
  }
}

// Quality 100 with full chroma: the touch frames come back within the round trip's rounding
// (YCbCr at 8 bits and q100's smallest quantiser step: under 1 DN on average, a few at single
// pixels, 4 measured), and the set says how it was stored.
TEST(Touch100k, FullChromaQuality100KeepsTheFramesAndIsRecorded) {
  TempDir tmp;
  WriterOptions o;
  o.jpeg_quality = 100;
  o.jpeg_full_chroma = true;
  const auto samples = testing::touch_set(2, 2);
  write_touch100k_set(tmp.path(), samples, o);
  const auto prov = nlohmann::json::parse(std::ifstream(tmp / "tlvlink_sim.json"));
  EXPECT_EQ(prov["writer"]["jpeg_chroma"], "4:4:4");
  EXPECT_EQ(prov["writer"]["jpeg_quality"], 100);
  const auto loaded = load_all(tmp.path());
  ASSERT_EQ(loaded.size(), samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const auto d = testing::image_diff(samples[i].touch, loaded[i].touch);
    EXPECT_LE(d.mean, 1.0) << i;
    EXPECT_LE(d.max, 5) << i;
  }
  TempDir plain;
  write_touch100k_set(plain.path(), samples);
  EXPECT_EQ(
      nlohmann::json::parse(std::ifstream(plain / "tlvlink_sim.json"))["writer"]["jpeg_chroma"],
      "4:2:0");
}

TEST(Touch100k, WithoutSidecarOnlyTheFormatsFields) {
  TempDir tmp;
  WriterOptions o;
  o.sidecar = false;
  write_touch100k_set(tmp.path(), testing::touch_set(1, 2), o);
  EXPECT_FALSE(std::filesystem::exists(tmp / "tlvlink_sim_samples.jsonl"));
  const auto loaded = load_all(tmp.path());
  ASSERT_EQ(loaded.size(), 2u);
  EXPECT_EQ(loaded[0].object_id, -1);
  EXPECT_EQ(loaded[0].material.class_id, -1);
  EXPECT_EQ(loaded[0].phrases.size(), 3u);
}

// The split the writer recorded in the sidecar comes back per sample, whole sessions at a time.
TEST(Touch100k, RecordedSplitFromTheSidecar) {
  TempDir tmp;
  WriterOptions o;
  o.test_fraction = 0.5;
  write_touch100k_set(tmp.path(), testing::touch_set(4, 2), o);
  Touch100kLoaderOptions lo;
  lo.load_images = false;
  auto loader = open_touch100k(tmp.path(), lo);
  ASSERT_TRUE(loader.ok()) << loader.error().message();
  std::map<std::string, std::set<Split>> by_session;
  datasets::TouchSample s;
  while ((*loader)->next(s).value()) by_session[s.session].insert((*loader)->recorded_split());
  ASSERT_EQ(by_session.size(), 4u);
  int test_sessions = 0;
  for (const auto& [session, splits] : by_session) {
    ASSERT_EQ(splits.size(), 1u) << session << " straddles the split";
    ASSERT_NE(*splits.begin(), Split::kAll) << session;
    test_sessions += *splits.begin() == Split::kTest ? 1 : 0;
  }
  EXPECT_EQ(test_sessions, 2);

  // Without the sidecar, or with a line whose split is garbage, nothing is recorded; the bad
  // line is counted with the sample's key.
  lo.use_sidecar = false;
  auto blind = open_touch100k(tmp.path(), lo);
  ASSERT_TRUE(blind.ok());
  ASSERT_TRUE((*blind)->next(s).value());
  EXPECT_EQ((*blind)->recorded_split(), Split::kAll);

  auto lines = testing::read_lines(tmp / "tlvlink_sim_samples.jsonl");
  auto first = nlohmann::json::parse(lines[0]);
  first["split"] = "validation";
  lines[0] = first.dump();
  std::ofstream out(tmp / "tlvlink_sim_samples.jsonl", std::ios::trunc);
  for (const std::string& line : lines) out << line << "\n";
  out.close();
  lo.use_sidecar = true;
  auto bad = open_touch100k(tmp.path(), lo);
  ASSERT_TRUE(bad.ok());
  ASSERT_TRUE((*bad)->next(s).value());
  EXPECT_EQ((*bad)->recorded_split(), Split::kAll);
  EXPECT_EQ((*bad)->report().count(ProblemKind::kSidecarMismatch), 1);
  EXPECT_NE((*bad)->report().summary().find("sidecar"), std::string::npos)
      << (*bad)->report().summary();
  ASSERT_TRUE((*bad)->next(s).value());
  EXPECT_NE((*bad)->recorded_split(), Split::kAll);
}

TEST(Touch100k, MissingAndCorruptImagesAreCountedWithPaths) {
  TempDir tmp;
  write_touch100k_set(tmp.path(), testing::touch_set(2, 3));
  const std::string missing = tmp / "touch/20220101_000001/0000000010.jpg";
  const std::string corrupt = tmp / "vision/20220101_000000/0000000003.jpg";
  std::filesystem::remove(missing);
  std::ofstream(corrupt, std::ios::trunc) << "this is not a JPEG";
  LoadReport report;
  const auto loaded = load_all(tmp.path(), &report);
  EXPECT_EQ(loaded.size(), 4u);
  EXPECT_EQ(report.loaded(), 4);
  EXPECT_EQ(report.missing_files(), 1);
  EXPECT_EQ(report.corrupt_files(), 1);
  ASSERT_EQ(report.problems().size(), 2u);
  EXPECT_EQ(report.problems()[0].path, corrupt);
  EXPECT_EQ(report.problems()[1].path, missing);
  EXPECT_EQ(report.summary(), "4 loaded; 1 missing file, 1 corrupt file");

  // Without vision required, the sample with a corrupt vision image still comes back.
  Touch100kLoaderOptions lenient;
  lenient.require_vision = false;
  const auto more = load_all(tmp.path(), nullptr, lenient);
  ASSERT_EQ(more.size(), 5u);
  EXPECT_TRUE(more[0].vision.rgb.empty());
}

TEST(Touch100k, MalformedLinesAreRejectedWithFileAndLine) {
  TempDir tmp;
  write_touch100k_set(tmp.path(), testing::touch_set(1, 3));
  auto lines = testing::read_lines(tmp / "data_list.json");
  lines.insert(lines.begin() + 1, "{\"img\": \"x.jpg\", \"sentence_desc\": ");  // line 2
  lines.insert(lines.begin() + 2, "");                                          // blank: skipped
  lines.insert(lines.begin() + 3,
               R"({"img": "../escape.jpg", "sentence_desc": "a", "phrase_desc": "b"})");
  lines.push_back(R"({"img": "a.jpg", "phrase_desc": "b"})");  // line 7
  testing::write_lines(tmp / "data_list.json", lines);
  LoadReport report;
  Touch100kLoaderOptions no_sidecar;  // the hand-inserted lines put the sidecar out of step
  no_sidecar.use_sidecar = false;
  const auto loaded = load_all(tmp.path(), &report, no_sidecar);
  EXPECT_EQ(loaded.size(), 3u);
  EXPECT_EQ(report.malformed_lines(), 3);
  ASSERT_GE(report.problems().size(), 3u);
  const std::string index = tmp / "data_list.json";
  EXPECT_EQ(report.problems()[0].path, index);
  EXPECT_EQ(report.problems()[0].line, 2);
  EXPECT_EQ(report.problems()[1].line, 4);
  EXPECT_NE(report.problems()[1].reason.find("../escape.jpg"), std::string::npos);
  EXPECT_EQ(report.problems()[2].line, 7);
  EXPECT_NE(report.problems()[0].to_string().find(index + ":2: malformed line"), std::string::npos);
}

TEST(Touch100k, SidecarOutOfStepIsReportedOnceAndDropped) {
  TempDir tmp;
  write_touch100k_set(tmp.path(), testing::touch_set(1, 3));
  auto side = testing::read_lines(tmp / "tlvlink_sim_samples.jsonl");
  std::swap(side[1], side[2]);
  testing::write_lines(tmp / "tlvlink_sim_samples.jsonl", side);
  LoadReport report;
  const auto loaded = load_all(tmp.path(), &report);
  ASSERT_EQ(loaded.size(), 3u);
  EXPECT_EQ(report.count(ProblemKind::kSidecarMismatch), 1);
  EXPECT_EQ(loaded[0].object_id, 100);
  EXPECT_EQ(loaded[1].object_id, -1);
  EXPECT_EQ(loaded[2].object_id, -1);
}

TEST(Touch100k, WriterRefusesBadInput) {
  TempDir tmp;
  write_touch100k_set(tmp.path(), testing::touch_set(1, 1));
  EXPECT_EQ(create_touch100k_writer(tmp.path(), {}).error().code(), ErrorCode::kInvalidArgument);
  TempDir tmp2;
  auto writer = create_touch100k_writer(tmp2.path(), {});
  ASSERT_TRUE(writer.ok());
  auto s = testing::touch_sample(0, 0);
  s.session = "../evil";
  EXPECT_EQ((*writer)->write(s).error().code(), ErrorCode::kInvalidArgument);
  s = testing::touch_sample(0, 0);
  s.touch.rgb.pop_back();
  EXPECT_EQ((*writer)->write(s).error().code(), ErrorCode::kInvalidArgument);
  WriterOptions bad;
  bad.jpeg_quality = 0;
  EXPECT_EQ(create_touch100k_writer(tmp2 / "x", bad).error().code(), ErrorCode::kInvalidArgument);
  bad = {};
  bad.generator_json = "[1, 2";
  EXPECT_EQ(create_touch100k_writer(tmp2 / "y", bad).error().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(open_touch100k(tmp2 / "nothing", {}).error().code(), ErrorCode::kIo);
}

TEST(Touch100k, LabelsOnlyAndScaledDecode) {
  TempDir tmp;
  write_touch100k_set(tmp.path(), testing::touch_set(1, 2));
  Touch100kLoaderOptions o;
  o.load_images = false;
  auto loaded = load_all(tmp.path(), nullptr, o);
  ASSERT_EQ(loaded.size(), 2u);
  EXPECT_TRUE(loaded[0].touch.rgb.empty());
  o = {};
  o.scale_denominator = 2;
  loaded = load_all(tmp.path(), nullptr, o);
  ASSERT_EQ(loaded.size(), 2u);
  EXPECT_EQ(loaded[0].touch.width, 16);
  EXPECT_EQ(loaded[0].touch.height, 12);
}

}  // namespace
}  // namespace tlvlink::datasets
