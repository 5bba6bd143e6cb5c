// Touch-and-Go writer -> loader: labels, session-disjoint splits, malformed label lines with
// file:line, missing and corrupt images with their paths, the session re-split.

#include "tlvlink/datasets/touch_and_go.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <vector>

#include "datasets/samples.h"

namespace tlvlink::datasets {
namespace {

using testing::TempDir;

constexpr double kTagJpegMeanTolerance = 3.0;  // q=90 on smooth images (see touch100k_test)

void write_tag_set(const std::string& dir, const std::vector<datasets::TouchSample>& samples,
                   double test_fraction = 0.3) {
  WriterOptions o;
  o.test_fraction = test_fraction;
  auto writer = create_tag_writer(dir, o);
  ASSERT_TRUE(writer.ok()) << writer.error().message();
  for (const auto& s : samples) ASSERT_TRUE((*writer)->write(s).ok());
  ASSERT_TRUE((*writer)->finish().ok());
}

struct Loaded {
  std::vector<std::string> keys;
  std::vector<datasets::TouchSample> samples;
  LoadReport report;
};

Loaded load(const std::string& dir, TagLoaderOptions options) {
  Loaded out;
  auto loader = open_touch_and_go(dir, options);
  EXPECT_TRUE(loader.ok()) << loader.error().message();
  if (!loader.ok()) return out;
  datasets::TouchSample s;
  for (;;) {
    auto more = (*loader)->next(s);
    EXPECT_TRUE(more.ok());
    if (!more.ok() || !more.value()) break;
    out.keys.push_back((*loader)->key());
    out.samples.push_back(s);
  }
  out.report = (*loader)->report();
  return out;
}

std::set<std::string> sessions_in(const std::string& label_file) {
  std::set<std::string> out;
  for (const auto& line : testing::read_lines(label_file))
    out.insert(line.substr(0, line.find('/')));
  return out;
}

TEST(TouchAndGo, RoundTripWithLabels) {
  TempDir tmp;
  const auto samples = testing::touch_set(10, 3);
  write_tag_set(tmp.path(), samples);
  EXPECT_TRUE(std::filesystem::exists(tmp / "20220101_000000/gelsight_frame/0000000003.jpg"));
  EXPECT_TRUE(std::filesystem::exists(tmp / "20220101_000000/video_frame/0000000003.jpg"));
  const auto train = testing::read_lines(tmp / "train.txt");
  ASSERT_FALSE(train.empty());
  EXPECT_EQ(train[0], "20220101_000000/0000000003.jpg,0");

  TagLoaderOptions o;
  o.split = Split::kAll;
  const Loaded all = load(tmp.path(), o);
  ASSERT_EQ(all.samples.size(), samples.size());
  EXPECT_EQ(all.report.problem_count(), 0) << all.report.summary();
  std::map<std::string, const datasets::TouchSample*> by_key;
  for (const auto& s : samples) {
    char name[32];
    std::snprintf(name, sizeof name, "%010d.jpg", s.frame_index);
    by_key[s.session + "/" + name] = &s;
  }
  for (size_t i = 0; i < all.samples.size(); ++i) {
    const datasets::TouchSample& want = *by_key.at(all.keys[i]);
    const datasets::TouchSample& got = all.samples[i];
    EXPECT_EQ(got.session, want.session);
    EXPECT_EQ(got.frame_index, want.frame_index);
    EXPECT_EQ(got.material.class_id, want.material.class_id);
    EXPECT_EQ(got.material.hard, want.material.hard);
    EXPECT_EQ(got.material.rough, want.material.rough);
    EXPECT_EQ(got.object_id, want.object_id);  // sidecar
    EXPECT_DOUBLE_EQ(got.contact.force_n, want.contact.force_n);
    EXPECT_LE(testing::image_diff(got.touch, want.touch).mean, kTagJpegMeanTolerance);
    EXPECT_LE(testing::image_diff(got.vision, want.vision).mean, kTagJpegMeanTolerance);
  }
  // Frames whose roughness is in between are not in the rough files.
  const size_t rough_lines = testing::read_lines(tmp / "train_rough.txt").size() +
                             testing::read_lines(tmp / "test_rough.txt").size();
  EXPECT_EQ(rough_lines, 20u);  // rough = frame % 3 - 1: one frame of three is -1
}

TEST(TouchAndGo, SplitsNeverShareASessionOrObject) {
  TempDir tmp;
  write_tag_set(tmp.path(), testing::touch_set(10, 3), 0.3);
  const auto train = sessions_in(tmp / "train.txt");
  const auto test = sessions_in(tmp / "test.txt");
  EXPECT_EQ(train.size(), 7u);
  EXPECT_EQ(test.size(), 3u);
  for (const auto& s : test) EXPECT_EQ(train.count(s), 0u) << s;
  for (const char* f : {"hard", "rough"}) {
    for (const auto& s : sessions_in(tmp / (std::string("test_") + f + ".txt")))
      EXPECT_EQ(train.count(s), 0u) << f << " " << s;
  }
  TagLoaderOptions o;
  o.split = Split::kTrain;
  std::set<int32_t> train_objects;
  for (const auto& s : load(tmp.path(), o).samples) train_objects.insert(s.object_id);
  o.split = Split::kTest;
  const Loaded test_loaded = load(tmp.path(), o);
  EXPECT_EQ(test_loaded.samples.size(), 9u);
  for (const auto& s : test_loaded.samples) EXPECT_EQ(train_objects.count(s.object_id), 0u);
}

TEST(TouchAndGo, ResplitBySessionIsDeterministicAndDisjoint) {
  TempDir tmp;
  write_tag_set(tmp.path(), testing::touch_set(12, 2));
  TagLoaderOptions o;
  o.resplit = HashSplit{0.4, 9};
  o.split = Split::kTrain;
  const Loaded train1 = load(tmp.path(), o);
  const Loaded train2 = load(tmp.path(), o);
  EXPECT_EQ(train1.keys, train2.keys);
  o.split = Split::kTest;
  const Loaded test = load(tmp.path(), o);
  EXPECT_EQ(train1.keys.size() + test.keys.size(), 24u);
  std::set<std::string> train_sessions;
  for (const auto& s : train1.samples) train_sessions.insert(s.session);
  for (const auto& s : test.samples) {
    EXPECT_EQ(train_sessions.count(s.session), 0u) << s.session;
    EXPECT_TRUE(hash_split_is_test(s.session, *o.resplit));
  }
  EXPECT_EQ(train1.report.problem_count(), 0) << train1.report.summary();
}

TEST(TouchAndGo, MalformedLabelLinesAreRejectedWithFileAndLine) {
  TempDir tmp;
  write_tag_set(tmp.path(), testing::touch_set(2, 2), 0.0);
  auto lines = testing::read_lines(tmp / "train.txt");
  ASSERT_EQ(lines.size(), 4u);
  lines.insert(lines.begin() + 1, "no comma here");                      // line 2
  lines.insert(lines.begin() + 2, "20220101_000000/0000000003.jpg,25");  // line 3: id > 19
  lines.insert(lines.begin() + 3, "20220101_000000/frame.jpg,1");        // line 4: not a frame
  lines.push_back("20220101_000001/0000000010.jpg,two");                 // line 8
  testing::write_lines(tmp / "train.txt", lines);
  auto rough = testing::read_lines(tmp / "train_rough.txt");
  rough.push_back("20220101_000000/0000000003.jpg,2");
  testing::write_lines(tmp / "train_rough.txt", rough);
  TagLoaderOptions o;
  o.use_sidecar = false;
  const Loaded loaded = load(tmp.path(), o);
  EXPECT_EQ(loaded.samples.size(), 4u);
  EXPECT_EQ(loaded.report.malformed_lines(), 5);
  const std::string train = tmp / "train.txt";
  std::vector<std::pair<std::string, int64_t>> where;
  for (const auto& p : loaded.report.problems()) where.emplace_back(p.path, p.line);
  const std::vector<std::pair<std::string, int64_t>> want = {
      {tmp / "train_rough.txt", static_cast<int64_t>(rough.size())},
      {train, 2},
      {train, 3},
      {train, 4},
      {train, 8}};
  EXPECT_EQ(where, want);
}

// Cuts a JPEG file inside its entropy-coded data, halfway between the start-of-scan marker and
// the end: the header still reads, the decode runs out of data (a download or copy cut short).
// Returns the new size (0 if the file has no SOS marker).
size_t truncate_in_scan_data(const std::string& path) {
  std::vector<char> bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  for (size_t i = 0; i + 1 < bytes.size(); ++i) {
    if (static_cast<uint8_t>(bytes[i]) == 0xFF && static_cast<uint8_t>(bytes[i + 1]) == 0xDA) {
      const size_t cut = i + (bytes.size() - i) / 2;
      std::filesystem::resize_file(path, cut);
      return cut;
    }
  }
  return 0;
}

TEST(TouchAndGo, MissingAndCorruptImagesAreCountedWithPaths) {
  TempDir tmp;
  write_tag_set(tmp.path(), testing::touch_set(2, 3), 0.0);  // all six frames in train.txt
  // train.txt lists session 0 frames 3, 10, 17, then session 1's: the truncated touch image is
  // met first, the missing camera image second.
  const std::string corrupt = tmp / "20220101_000000/gelsight_frame/0000000010.jpg";
  const std::string missing = tmp / "20220101_000001/video_frame/0000000003.jpg";
  std::filesystem::remove(missing);
  const auto size = std::filesystem::file_size(corrupt);
  const size_t cut = truncate_in_scan_data(corrupt);
  ASSERT_GT(cut, 0u);
  ASSERT_LT(cut + 16, size);
  TagLoaderOptions o;
  o.split = Split::kAll;
  const Loaded loaded = load(tmp.path(), o);
  EXPECT_EQ(loaded.samples.size(), 4u);
  EXPECT_EQ(loaded.report.loaded(), 4);
  EXPECT_EQ(loaded.report.missing_files(), 1);
  EXPECT_EQ(loaded.report.corrupt_files(), 1);
  ASSERT_EQ(loaded.report.problems().size(), 2u) << loaded.report.summary();
  EXPECT_EQ(loaded.report.problems()[0].path, corrupt);
  EXPECT_EQ(loaded.report.problems()[0].kind, ProblemKind::kCorruptFile);
  EXPECT_EQ(loaded.report.problems()[1].path, missing);
  EXPECT_EQ(loaded.report.problems()[1].kind, ProblemKind::kMissingFile);
  EXPECT_EQ(loaded.report.summary(), "4 loaded; 1 missing file, 1 corrupt file");
  // The printed problem line names the file, the kind and the decoder's reason.
  const std::string line = loaded.report.problems()[0].to_string();
  EXPECT_EQ(line.rfind(corrupt + ": corrupt file: ", 0), 0u) << line;
  for (const std::string& key : loaded.keys) {
    EXPECT_NE(key, "20220101_000000/0000000010.jpg");
    EXPECT_NE(key, "20220101_000001/0000000003.jpg");
  }

  // Without vision required, the frame whose camera image is missing comes back without it; the
  // truncated touch image still drops its frame.
  o.require_vision = false;
  const Loaded lenient = load(tmp.path(), o);
  ASSERT_EQ(lenient.samples.size(), 5u);
  EXPECT_EQ(lenient.report.missing_files(), 1);
  EXPECT_EQ(lenient.report.corrupt_files(), 1);
  size_t without_vision = 0;
  for (size_t i = 0; i < lenient.samples.size(); ++i) {
    if (!lenient.samples[i].vision.rgb.empty()) continue;
    ++without_vision;
    EXPECT_EQ(lenient.keys[i], "20220101_000001/0000000003.jpg");
  }
  EXPECT_EQ(without_vision, 1u);
}

// A JPEG cut inside its header tables makes tjDecompressHeader3 fail and leaves the thread's
// reused decompressor unusable (libjpeg-turbo 2.1.5): without tools/io/jpeg.cc starting a fresh
// one after an error, the next valid image read as 0x0 and one bad file cost two samples.
TEST(TouchAndGo, JpegCutInsideItsHeaderDoesNotSpoilTheNextImage) {
  TempDir tmp;
  write_tag_set(tmp.path(), testing::touch_set(1, 3), 0.0);
  const std::string corrupt = tmp / "20220101_000000/gelsight_frame/0000000010.jpg";
  std::filesystem::resize_file(corrupt, 300);  // inside the quantisation/Huffman tables
  TagLoaderOptions o;
  o.split = Split::kAll;
  const Loaded loaded = load(tmp.path(), o);
  EXPECT_EQ(loaded.samples.size(), 2u) << loaded.report.summary();
  EXPECT_EQ(loaded.report.corrupt_files(), 1);
}

TEST(TouchAndGo, MissingLabelFiles) {
  TempDir tmp;
  write_tag_set(tmp.path(), testing::touch_set(2, 3), 0.0);
  std::filesystem::remove(tmp / "train_hard.txt");
  std::filesystem::remove(tmp / "train_rough.txt");
  TagLoaderOptions o;
  o.use_sidecar = false;
  const Loaded loaded = load(tmp.path(), o);
  ASSERT_EQ(loaded.samples.size(), 6u);
  // Hard follows the class rule (class 0 concrete: hard; 1 plastic: hard), rough is unknown.
  for (const auto& s : loaded.samples) {
    EXPECT_TRUE(s.material.hard);
    EXPECT_EQ(s.material.rough, -1);
  }
  std::filesystem::remove(tmp / "train.txt");
  EXPECT_EQ(open_touch_and_go(tmp.path(), o).error().code(), ErrorCode::kIo);
}

TEST(TouchAndGo, ParseLabelLine) {
  auto ok = parse_tag_label_line("20220410_031604/0000000216.jpg,3 \r");
  ASSERT_TRUE(ok.ok()) << ok.error().message();
  EXPECT_EQ(ok->session, "20220410_031604");
  EXPECT_EQ(ok->frame_index, 216);
  EXPECT_EQ(ok->label, 3);
  EXPECT_FALSE(parse_tag_label_line("20220410_031604/0000000216.jpg,").ok());
  EXPECT_FALSE(parse_tag_label_line("../0000000216.jpg,1").ok());
  EXPECT_FALSE(parse_tag_label_line("0000000216.jpg,1").ok());
}

}  // namespace
}  // namespace tlvlink::datasets
