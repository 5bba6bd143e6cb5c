// A camera recording replaces an existing file only when it is complete: frames stream into a
// temporary beside it, close() renames it into place (tlvlink/atomic_file.h).
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/temp_dir.h"
#include "tlvlink/capture/recording.h"

namespace tlvlink::capture {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(RecordingWriter, AnExistingFileIsReplacedOnlyAtClose) {
  testing::TempDir dir("recording");
  const std::string path = dir / "cam.tlvraw";
  std::ofstream(path, std::ios::binary) << "old recording";
  RecordingFormat format;
  format.format = {image::PixelFormat::kGrey, 4, 2, 4};
  format.fps_numerator = 25;
  WriterOptions options;
  options.overwrite = true;
  auto w = RecordingWriter::create(path, format, options);
  ASSERT_TRUE(w.ok()) << w.error().message();
  const std::vector<uint8_t> frame(8, 7);
  ASSERT_TRUE(w->append(frame, 1'000'000, 0).ok());
  EXPECT_EQ(slurp(path), "old recording");  // untouched while recording
  ASSERT_TRUE(w->close().ok());
  auto r = RecordingReader::open(path);
  ASSERT_TRUE(r.ok()) << r.error().message();
  int temporaries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path()))
    temporaries += e.path().filename().string().find(".tmp-") != std::string::npos;
  EXPECT_EQ(temporaries, 0);
}

TEST(RecordingWriter, WithoutOverwriteAnExistingFileIsAnError) {
  testing::TempDir dir("recording");
  const std::string path = dir / "cam.tlvraw";
  std::ofstream(path, std::ios::binary) << "old recording";
  RecordingFormat format;
  format.format = {image::PixelFormat::kGrey, 4, 2, 4};
  auto w = RecordingWriter::create(path, format);
  ASSERT_FALSE(w.ok());
  EXPECT_NE(std::string(w.error().message()).find(path), std::string::npos);
  EXPECT_EQ(slurp(path), "old recording");
}

}  // namespace
}  // namespace tlvlink::capture
