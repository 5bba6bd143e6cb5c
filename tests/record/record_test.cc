// `tlvlink record`'s library: image folders become one camera stream (JPEG files byte for byte,
// other files encoded), held frames are repeats, and a frame of another size is an error that
// leaves no recording behind.

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/temp_dir.h"
#include "tlvlink/capture/recording.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/record/record.h"

namespace tlvlink::record {
namespace {

namespace fs = std::filesystem;

void write_ppm(const fs::path& p, int w, int h, int shade) {
  std::ofstream out(p, std::ios::binary);
  out << "P6\n" << w << " " << h << "\n255\n";
  for (int i = 0; i < w * h * 3; ++i) out.put(static_cast<char>((shade + i) & 0xFF));
}

std::vector<uint8_t> jpeg_of(int w, int h, int shade) {
  image::Image im;
  im.width = w;
  im.height = h;
  im.channels = 3;
  im.pixels.resize(static_cast<size_t>(w * h * 3));
  for (size_t i = 0; i < im.pixels.size(); ++i) im.pixels[i] = static_cast<uint8_t>(shade + i);
  auto j = image::encode_jpeg(im, 90);
  EXPECT_TRUE(j.ok());
  return std::move(j).value();
}

TEST(Record, ImageFolderBecomesOneStreamWithHeldFrames) {
  const ::tlvlink::testing::TempDir tmp("record_ppm");  // removed at the end of the test
  const fs::path d = tmp.path();
  for (int k = 0; k < 3; ++k) write_ppm(d / ("f" + std::to_string(k) + ".ppm"), 32, 24, k * 40);
  RecordOptions o;
  o.input = d.string();
  o.hold = 4;
  o.fps = 60;
  const std::string out = (d / "out.tlvraw").string();
  auto r = record_frames(o, out);
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_EQ(r->images, 3);
  EXPECT_EQ(r->frames, 12);
  EXPECT_FALSE(r->stored_as_is);
  auto rec = capture::RecordingReader::open(out);
  ASSERT_TRUE(rec.ok());
  EXPECT_EQ(rec->summary().frames, 12u);
  EXPECT_EQ(rec->summary().repeats, 9u);
  EXPECT_EQ(rec->summary().format.format.format, image::PixelFormat::kMjpeg);
  EXPECT_EQ(rec->summary().format.format.width, 32);
  EXPECT_NEAR(rec->summary().format.nominal_fps(), 60.0, 1e-9);
  // An existing recording is not replaced without overwrite.
  auto again = record_frames(o, out);
  ASSERT_FALSE(again.ok());
  EXPECT_NE(std::string(again.error().message()).find("exists"), std::string::npos);
}

TEST(Record, JpegFilesAreKeptByteForByte) {
  const ::tlvlink::testing::TempDir tmp("record_jpeg");  // removed at the end of the test
  const fs::path d = tmp.path();
  std::vector<std::vector<uint8_t>> files;
  for (int k = 0; k < 2; ++k) {
    files.push_back(jpeg_of(40, 30, k * 50));
    std::ofstream(d / ("f" + std::to_string(k) + ".jpg"), std::ios::binary)
        .write(reinterpret_cast<const char*>(files.back().data()),
               static_cast<std::streamsize>(files.back().size()));
  }
  RecordOptions o;
  o.input = d.string();
  const std::string out = (d / "out.tlvraw").string();
  auto r = record_frames(o, out);
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_TRUE(r->stored_as_is);
  auto rec = capture::RecordingReader::open(out);
  ASSERT_TRUE(rec.ok());
  std::vector<uint8_t> buf(rec->summary().max_frame_bytes);
  uint64_t at = rec->first_record();
  for (int k = 0; k < 2; ++k) {
    capture::RecordInfo info;
    auto have = rec->record_at(at, info);
    ASSERT_TRUE(have.ok() && *have);
    ASSERT_TRUE(rec->read_frame(info, buf, true).ok());
    EXPECT_EQ(std::vector<uint8_t>(buf.begin(), buf.begin() + info.bytes),
              files[static_cast<size_t>(k)]);
    at = info.next;
  }
}

TEST(Record, AFrameOfAnotherSizeIsAnErrorNamingItAndLeavesNoRecording) {
  const ::tlvlink::testing::TempDir tmp("record_sizes");  // removed at the end of the test
  const fs::path d = tmp.path();
  write_ppm(d / "a.ppm", 32, 24, 0);
  write_ppm(d / "b.ppm", 24, 32, 0);
  RecordOptions o;
  o.input = d.string();
  const std::string out = (d / "out.tlvraw").string();
  auto r = record_frames(o, out);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code(), ErrorCode::kShapeMismatch);
  EXPECT_NE(std::string(r.error().message()).find("b.ppm is 24x32"), std::string::npos)
      << r.error().message();
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));
  RecordOptions none;
  none.input = (d / "missing").string();
  EXPECT_FALSE(record_frames(none, out).ok());
}

}  // namespace
}  // namespace tlvlink::record
