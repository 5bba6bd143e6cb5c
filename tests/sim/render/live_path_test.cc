// LivePath: an already rendered frame through the sensor's raw camera output and the board's
// decoder is what RawCamera::render + RawDecoder give for the same scene, except next to the
// border (where render() draws the gel's periphery and encode_frame repeats the edge pixels).
#include "tlvlink/sim/live_path.h"  // first: the public header compiles on its own

#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "sim/render/raw_test_util.h"
#include "sim/render/render_test_util.h"

namespace tlvlink::sim {
namespace {

std::unique_ptr<LivePath> make_live_path(std::string_view name) {
  auto profile = sensor_profile(name);
  EXPECT_TRUE(profile.ok());
  if (!profile.ok()) return nullptr;
  auto path = LivePath::create(profile.value());
  EXPECT_TRUE(path.ok()) << path.error().message();
  return path.ok() ? std::move(path.value()) : nullptr;
}

// Largest |a - b| over the pixels at least `margin` px from every border.
int max_difference_inside(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b,
                          int32_t width, int32_t height, int32_t margin) {
  int worst = 0;
  for (int32_t y = margin; y < height - margin; ++y) {
    for (int32_t x = margin; x < width - margin; ++x) {
      const size_t i =
          (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * 3;
      for (size_t k = 0; k < 3; ++k) worst = std::max(worst, std::abs(a[i + k] - b[i + k]));
    }
  }
  return worst;
}

// Inside the frame the two paths are the same bytes: the raw pixels there are resampled from the
// processed frame alone, and JPEG blocks and YUYV pairs are local. Margin: the Mini's raw
// periphery reaches the processed view through the decode's 8x8 blocks at the crop line and the
// resampler's taps; measured, the paths differ in the outermost pixel only (by up to 4 DN).
TEST(SimLivePath, EqualsTheRawCameraAndDecoderInsideTheFrame) {
  ContactScene rough = testing::sphere(8, 10);
  rough.texture.sq_um = 30;
  rough.geometry.center_x_mm = 2;
  RenderOptions markers;
  markers.markers = true;
  for (std::string_view name : {"gelsight-mini", "digit", "gelsight-r1.5"}) {
    SCOPED_TRACE(std::string(name));
    auto camera = testing::make_camera(name, 4);
    auto decoder = testing::make_decoder(name);
    auto live = make_live_path(name);
    ASSERT_TRUE(camera && decoder && live);
    for (const ContactScene& s : {testing::sphere(4), rough}) {
      const RawFrame raw = testing::render_raw(*camera, s, markers, 7);
      const std::vector<uint8_t> expected = testing::recover_ok(*decoder, raw.bytes);
      std::vector<uint8_t> frame = raw.processed.rgb;
      const Status st = live->apply(frame);
      ASSERT_TRUE(st.ok()) << st.error().message();
      EXPECT_EQ(
          max_difference_inside(frame, expected, raw.processed.width, raw.processed.height, 1), 0);
      // And the frame did go through the camera: not the processed frame any more.
      EXPECT_NE(frame, raw.processed.rgb);
    }
  }
}

TEST(SimLivePath, IsDeterministic) {
  auto renderer = testing::make_renderer("gelsight-mini", 2);
  auto live = make_live_path("gelsight-mini");
  ASSERT_TRUE(renderer && live);
  const Frame f = testing::render_ok(*renderer, testing::sphere(5), {}, 3);
  std::vector<uint8_t> a = f.rgb, b = f.rgb;
  ASSERT_TRUE(live->apply(a).ok());
  ASSERT_TRUE(live->apply(b).ok());
  EXPECT_EQ(a, b);
}

TEST(SimLivePath, RejectsAFrameOfAnotherSize) {
  auto live = make_live_path("gelsight-mini");
  ASSERT_TRUE(live);
  std::vector<uint8_t> wrong(320 * 239 * 3, 128);
  const Status st = live->apply(wrong);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code(), ErrorCode::kShapeMismatch);
  EXPECT_NE(std::string(st.error().message()).find("gelsight-mini"), std::string::npos)
      << st.error().message();
}

}  // namespace
}  // namespace tlvlink::sim
