// Bad raw input is an error value that names the stream and says what was expected: truncated,
// empty, non-JPEG and wrong-size MJPEG frames; YUYV frames of the wrong byte count; invalid
// options and raw geometry.
#include <string>

#include <gtest/gtest.h>

#include "sim/render/raw_test_util.h"
#include "sim/render/render_test_util.h"

namespace tlvlink::sim {
namespace {

using testing::make_camera;
using testing::make_decoder;
using testing::render_raw;

// The error's code is kFormat and its message contains every one of `parts`.
void expect_format_error(RawDecoder& decoder, const std::vector<uint8_t>& bytes,
                         std::initializer_list<const char*> parts) {
  std::vector<uint8_t> rgb;
  const Status st = decoder.recover(bytes, rgb);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code(), ErrorCode::kFormat);
  const std::string message = st.error().message();
  for (const char* part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
}

TEST(SimRenderRawErrors, BadMjpegFramesAreNamed) {
  auto camera = make_camera("gelsight-mini");
  auto decoder = make_decoder("gelsight-mini");
  auto r15 = make_camera("gelsight-r1.5");
  ASSERT_TRUE(camera && decoder && r15);
  const RawFrame good = render_raw(*camera, testing::sphere(4), RenderOptions{});
  // Cut in half: the header is intact, the scan data ends early.
  std::vector<uint8_t> truncated(
      good.bytes.begin(), good.bytes.begin() + static_cast<ptrdiff_t>(good.bytes.size() / 2));
  expect_format_error(*decoder, truncated,
                      {"gelsight-mini raw frame", "truncated or corrupt JPEG",
                       std::to_string(truncated.size()).c_str()});
  // Only the first 100 bytes: not even a complete header.
  expect_format_error(*decoder, std::vector<uint8_t>(good.bytes.begin(), good.bytes.begin() + 100),
                      {"gelsight-mini raw frame", "JPEG header", "100 bytes"});
  expect_format_error(*decoder, {}, {"gelsight-mini raw frame", "empty"});
  expect_format_error(*decoder, std::vector<uint8_t>(5000, 0x55),
                      {"JPEG header", "Not a JPEG file"});
  // A valid JPEG of another camera's size.
  const RawFrame small = render_raw(*r15, testing::sphere(4), RenderOptions{});
  expect_format_error(*decoder, small.bytes,
                      {"gelsight-mini raw frame", "JPEG frame is 320x240, expected 3280x2464"});
  // The decoder keeps working after errors, also after a frame cut inside its header tables
  // (libjpeg-turbo 2.1 leaves the handle of such a header read unusable for the next frame).
  std::vector<uint8_t> reference, rgb;
  ASSERT_TRUE(make_decoder("gelsight-mini")->recover(good.bytes, reference).ok());
  expect_format_error(*decoder, std::vector<uint8_t>(good.bytes.begin(), good.bytes.begin() + 300),
                      {"gelsight-mini raw frame", "300 bytes"});
  const Status st = decoder->recover(good.bytes, rgb);
  ASSERT_TRUE(st.ok()) << st.error().message();
  EXPECT_EQ(rgb, reference);
}

TEST(SimRenderRawErrors, YuyvFramesOfTheWrongSizeAreNamed) {
  auto decoder = make_decoder("digit");
  ASSERT_NE(decoder, nullptr);
  expect_format_error(*decoder, std::vector<uint8_t>(153599, 128),
                      {"digit raw frame", "153599 bytes", "320x240 YUYV", "153600 bytes"});
  expect_format_error(*decoder, std::vector<uint8_t>(320 * 240 * 3, 128),
                      {"230400 bytes", "153600 bytes"});  // an RGB frame is not YUYV
  expect_format_error(*decoder, {}, {"0 bytes"});
  std::vector<uint8_t> rgb;
  EXPECT_TRUE(decoder->recover(std::vector<uint8_t>(153600, 128), rgb).ok());
  EXPECT_EQ(rgb.size(), 320u * 240u * 3u);
}

TEST(SimRenderRawErrors, InvalidOptionsAndGeometryAreRejected) {
  const SensorProfile mini = sensor_profile("gelsight-mini").value();
  RawOptions q0;
  q0.jpeg_quality = 0;
  auto camera = RawCamera::create(mini, 1, q0);
  ASSERT_FALSE(camera.ok());
  EXPECT_NE(std::string(camera.error().message()).find("quality 0"), std::string::npos);
  RecoverOptions s3;
  s3.jpeg_scale_denominator = 3;
  auto decoder = RawDecoder::create(mini, s3);
  ASSERT_FALSE(decoder.ok());
  EXPECT_EQ(decoder.error().code(), ErrorCode::kInvalidArgument);
  // A square raw frame cannot become a 4:3 processed frame by cropping equal fractions.
  SensorProfile square = mini;
  square.raw_width = square.raw_height = 2464;
  auto layout = raw_layout(square);
  ASSERT_FALSE(layout.ok());
  EXPECT_NE(std::string(layout.error().message()).find("aspect"), std::string::npos);
  EXPECT_FALSE(RawCamera::create(square, 1).ok());
  // DIGIT's portrait frame from a landscape camera needs raw_transposed.
  SensorProfile digit = sensor_profile("digit").value();
  digit.raw_transposed = false;
  EXPECT_FALSE(raw_layout(digit).ok());
  // YUYV pairs pixels: an odd raw width cannot be sent.
  SensorProfile odd = sensor_profile("digit").value();
  odd.raw_width = 321;
  odd.raw_height = 241;
  odd.width = 241;
  odd.height = 321;
  auto odd_layout = raw_layout(odd);
  ASSERT_FALSE(odd_layout.ok());
  EXPECT_NE(std::string(odd_layout.error().message()).find("even"), std::string::npos);
  // raw_crop is range-checked with the profile.
  SensorProfile crop = mini;
  crop.raw_crop = 0.5;
  EXPECT_NE(std::string(raw_layout(crop).error().message()).find("sensor.raw_crop"),
            std::string::npos);
}

}  // namespace
}  // namespace tlvlink::sim
