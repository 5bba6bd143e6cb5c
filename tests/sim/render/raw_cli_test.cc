// `tlvlink sim frame --raw`: the file holds the camera's bytes (MJPEG of the camera's size,
// YUYV of the exact byte count), recovers to the processed frame written next to it, and the
// extension must match the format.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "sim/render/raw_test_util.h"
#include "support/cli_run.h"
#include "support/temp_dir.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/image.h"
#include "tlvlink/io/pnm.h"

namespace tlvlink::sim {
namespace {

using ::tlvlink::testing::run_tlvlink;
using ::tlvlink::testing::TempDir;

TEST(SimRenderRawCli, MiniWritesMjpegOfTheCameraSize) {
  TempDir tmp("sim_raw_cli");
  const auto run = run_tlvlink("sim frame --sensor gelsight-mini --markers --raw " +
                               (tmp / "mini.jpg") + " -o " + (tmp / "mini.ppm"));
  ASSERT_RUN(run, 0);
  EXPECT_NE(run.out.find("raw mjpeg 3280x2464"), std::string::npos) << run.out;
  auto jpeg = tools::read_jpeg(tmp / "mini.jpg", 8);
  ASSERT_TRUE(jpeg.ok()) << jpeg.error().message();
  EXPECT_EQ(jpeg->width, 410);  // 3280 / 8
  EXPECT_EQ(jpeg->height, 308);
  auto ppm = tools::read_pnm(tmp / "mini.ppm");
  ASSERT_TRUE(ppm.ok());
  EXPECT_EQ(ppm->width, 320);
  EXPECT_EQ(ppm->height, 240);
}

TEST(SimRenderRawCli, RawFileRecoversToTheProcessedFile) {
  TempDir tmp("sim_raw_cli");
  // PPM keeps the processed frame exact; the R1.5's raw MJPEG is the same view.
  const auto run = run_tlvlink("sim frame --sensor gelsight-r1.5 --x 2 --force 6 --raw " +
                               (tmp / "r15.jpg") + " -o " + (tmp / "r15.ppm"));
  ASSERT_RUN(run, 0);
  auto bytes = tools::read_file(tmp / "r15.jpg", size_t{1} << 24);
  auto ppm = tools::read_pnm(tmp / "r15.ppm");
  ASSERT_TRUE(bytes.ok() && ppm.ok());
  auto decoder = testing::make_decoder("gelsight-r1.5");
  ASSERT_NE(decoder, nullptr);
  const auto* data = reinterpret_cast<const uint8_t*>(bytes->data());
  const auto rgb = testing::recover_ok(*decoder, std::vector<uint8_t>(data, data + bytes->size()));
  // gelsight-r1.5's bound with camera noise (raw_camera_test.cc).
  EXPECT_LE(testing::closeness(rgb, ppm->pixels).mean_abs, 2.75);
}

TEST(SimRenderRawCli, DigitWritesYuyvAndChecksTheExtension) {
  TempDir tmp("sim_raw_cli");
  const auto run = run_tlvlink("sim frame --sensor digit --raw " + (tmp / "digit.yuyv"));
  ASSERT_RUN(run, 0);
  EXPECT_EQ(std::filesystem::file_size(tmp / "digit.yuyv"), 320u * 240u * 2u);
  const auto wrong = run_tlvlink("sim frame --sensor digit --raw " + (tmp / "digit.jpg"));
  EXPECT_RUN(wrong, 2);
  EXPECT_NE(wrong.out.find(".yuyv"), std::string::npos) << wrong.out;
  EXPECT_FALSE(std::filesystem::exists(tmp / "digit.jpg"));
  const auto nothing = run_tlvlink("sim frame --sensor digit");
  EXPECT_RUN(nothing, 2);
  EXPECT_NE(nothing.out.find("nothing to write"), std::string::npos) << nothing.out;
}

}  // namespace
}  // namespace tlvlink::sim
