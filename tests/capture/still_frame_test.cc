// Still frames into a sensor's processed view (runtime/capture still_frame.h) and the host's
// image-file front end (tools/io sensor_frame.h): a camera frame is cut exactly as the daemon's
// FrameDecoder cuts it, a view is taken as it is, any other size is refused naming the sizes.

#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/capture/still_frame.h"
#include "tlvlink/image/frame_decoder.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/sensor_frame.h"

namespace tlvlink::capture {
namespace {

image::Image gradient(int32_t w, int32_t h) {
  image::Image im{w, h, 3,
                  std::vector<uint8_t>(static_cast<size_t>(w) * static_cast<size_t>(h) * 3)};
  for (int32_t y = 0; y < h; ++y)
    for (int32_t x = 0; x < w; ++x)
      for (int32_t c = 0; c < 3; ++c)
        im.pixels[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 3 +
                  static_cast<size_t>(c)] =
            static_cast<uint8_t>((x * 255 / w + y * 128 / h + 60 * c) % 256);
  return im;
}

std::span<const std::byte> bytes_of(const std::vector<uint8_t>& v) {
  return std::as_bytes(std::span<const uint8_t>(v));
}

// A binary PPM of the image (what `tlvlink sim frame -o x.ppm` writes).
std::vector<std::byte> ppm(const image::Image& im) {
  const std::string header =
      "P6\n" + std::to_string(im.width) + " " + std::to_string(im.height) + "\n255\n";
  std::vector<std::byte> out(header.size() + im.pixels.size());
  std::memcpy(out.data(), header.data(), header.size());
  std::memcpy(out.data() + header.size(), im.pixels.data(), im.pixels.size());
  return out;
}

TEST(StillFrame, ClassifiesByTheSensorsSizes) {
  const SensorModel& mini = *find_sensor_model("gelsight-mini");
  EXPECT_EQ(classify_still(mini, 3280, 2464).value(), StillKind::kCameraFrame);
  EXPECT_EQ(classify_still(mini, 320, 240).value(), StillKind::kProcessedView);
  auto odd = classify_still(mini, 300, 400);
  ASSERT_FALSE(odd.ok());
  EXPECT_EQ(odd.error().code(), ErrorCode::kShapeMismatch);
  EXPECT_NE(std::string(odd.error().message()).find("3280x2464"), std::string::npos);
  const auto of_3280 = sensors_of_size(3280, 2464);
  ASSERT_EQ(of_3280.size(), 1u);
  EXPECT_EQ(of_3280[0]->name, "gelsight-mini");
  EXPECT_TRUE(sensors_of_size(17, 13).empty());
}

TEST(StillFrame, AMiniCameraJpegIsCutExactlyAsTheDaemonCutsIt) {
  const SensorModel& mini = *find_sensor_model("gelsight-mini");
  const image::Image camera = gradient(3280, 2464);
  auto jpeg = image::encode_jpeg(camera, 90);
  ASSERT_TRUE(jpeg.ok());
  auto view = view_from_still_jpeg(*jpeg, mini, "camera.jpg");
  ASSERT_TRUE(view.ok()) << view.error().message();
  EXPECT_EQ(view->width, 320);
  EXPECT_EQ(view->height, 240);
  // The daemon's decoder on the same bytes.
  auto decoder =
      image::FrameDecoder::create({image::PixelFormat::kMjpeg, 3280, 2464, 0}, mini.view);
  ASSERT_TRUE(decoder.ok());
  std::vector<uint8_t> daemon(decoder->output_bytes());
  ASSERT_TRUE(decoder->decode(*jpeg, daemon, "daemon").ok());
  EXPECT_EQ(view->pixels, daemon);
  // The same frame through the host front end, detected by its size.
  auto f = tools::sensor_frame_from_bytes(bytes_of(*jpeg), "camera.jpg", "");
  ASSERT_TRUE(f.ok()) << f.error().message();
  EXPECT_EQ(f->sensor, "gelsight-mini");
  EXPECT_EQ(f->view.pixels, daemon);
  EXPECT_NE(f->note.find("cut to its 320x240 view"), std::string::npos);
}

TEST(StillFrame, AViewIsTakenAsItIsAndOddSizesAreRefused) {
  const image::Image view = gradient(320, 240);
  const std::vector<std::byte> png = ppm(view);
  auto f = tools::sensor_frame_from_bytes(png, "view.png", "");
  ASSERT_TRUE(f.ok()) << f.error().message();
  EXPECT_EQ(f->view.pixels, view.pixels);
  EXPECT_TRUE(f->note.empty());
  const std::vector<std::byte> wide = ppm(gradient(400, 200));
  auto refused = tools::sensor_frame_from_bytes(wide, "wide.png", "");
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code(), ErrorCode::kShapeMismatch);
  EXPECT_NE(std::string(refused.error().message()).find("wide.png: a 400x200 frame"),
            std::string::npos);
  auto named = tools::sensor_frame_from_bytes(wide, "wide.png", "gelsight-mini");
  ASSERT_FALSE(named.ok());
  EXPECT_NE(std::string(named.error().message()).find("gelsight-mini camera frame (3280x2464)"),
            std::string::npos);
  auto unknown = tools::sensor_frame_from_bytes(png, "view.png", "gelsight-max");
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().code(), ErrorCode::kInvalidArgument);
}

TEST(StillFrame, ProcessedMiniFramesHaveAProfileThatTakesThemWhole) {
  // gsrobotics hands users 320x240 frames already cut: the profile decodes them untouched, in the
  // daemon (its FrameDecoder) as in the host tools, where `gelsight-mini` would cut 15 % again.
  const SensorModel* processed = find_sensor_model("gelsight-mini-processed");
  ASSERT_NE(processed, nullptr);
  EXPECT_EQ(processed->width, 320);
  EXPECT_EQ(processed->height, 240);
  EXPECT_EQ(processed->view.crop, 0.0);
  const image::Image view = gradient(320, 240);
  auto jpeg = image::encode_jpeg(view, 95);
  ASSERT_TRUE(jpeg.ok());
  auto want = image::decode_jpeg(*jpeg, "ref");
  ASSERT_TRUE(want.ok());
  auto d = image::FrameDecoder::create({processed->format, processed->width, processed->height, 0},
                                       processed->view);
  ASSERT_TRUE(d.ok()) << d.error().message();
  std::vector<uint8_t> out(d->output_bytes());
  ASSERT_TRUE(d->decode(*jpeg, out, "cam").ok());
  EXPECT_EQ(out, want->pixels);
  auto f = tools::sensor_frame_from_bytes(ppm(view), "saved.png", "gelsight-mini-processed");
  ASSERT_TRUE(f.ok()) << f.error().message();
  EXPECT_EQ(f->view.pixels, view.pixels);
}

TEST(StillFrame, ADigitCameraFrameIsTurnedUpright) {
  // DIGIT's camera sends 320x240 transposed; its view is the 240x320 portrait frame.
  const SensorModel& digit = *find_sensor_model("digit");
  const image::Image camera = gradient(320, 240);
  auto v = view_from_still_rgb(camera.view(), digit, "digit.png");
  ASSERT_TRUE(v.ok()) << v.error().message();
  EXPECT_EQ(v->width, 240);
  EXPECT_EQ(v->height, 320);
  // upright = flip_top_bottom(transpose(camera)): upright (x, y) = camera (319 - y, x).
  EXPECT_EQ(v->pixels[(5 * 240 + 7) * 3], camera.pixels[(7 * 320 + (319 - 5)) * 3]);
}

}  // namespace
}  // namespace tlvlink::capture
