// MJPEG error handling with real JPEG frames (vivid has no MJPEG, so these buffers are injected
// into the same checks and accounting the V4L2 source runs on every dequeued buffer): corrupt,
// truncated, zero-length and EOI-less frames are counted and skipped, good ones delivered.
#include <gtest/gtest.h>

#include <vector>

#include "tlvlink/capture/frame_accounting.h"
#include "tlvlink/image/jpeg.h"

namespace tlvlink::capture {
namespace {

// A GelSight-Mini-sized frame (3280x2464, what the camera sends) with smooth content.
std::vector<uint8_t> mini_jpeg() {
  image::Image img;
  img.width = 3280;
  img.height = 2464;
  img.channels = 3;
  img.pixels.resize(static_cast<size_t>(img.width) * img.height * 3);
  for (int32_t y = 0; y < img.height; ++y) {
    for (int32_t x = 0; x < img.width; ++x) {
      uint8_t* p = &img.pixels[(static_cast<size_t>(y) * img.width + x) * 3];
      p[0] = static_cast<uint8_t>(x * 255 / img.width);
      p[1] = static_cast<uint8_t>(y * 255 / img.height);
      p[2] = static_cast<uint8_t>((x + y) & 0xFF);
    }
  }
  auto jpeg = image::encode_jpeg(img, 85);
  EXPECT_TRUE(jpeg.ok());
  return jpeg.ok() ? std::move(*jpeg) : std::vector<uint8_t>();
}

TEST(MjpegStream, RealFramePassesAndDecodes) {
  const auto j = mini_jpeg();
  ASSERT_GT(j.size(), 1000u);
  EXPECT_EQ(check_mjpeg(j), FrameProblem::kNone);
  auto img = image::decode_jpeg(j, "mini", 8);
  ASSERT_TRUE(img.ok()) << img.error().message();
  EXPECT_EQ(img->width, 410);
}

TEST(MjpegStream, TruncationsAreCaught) {
  const auto j = mini_jpeg();
  for (size_t keep :
       {j.size() - 1, j.size() - 2, j.size() * 9 / 10, j.size() / 2, size_t{600}, size_t{3}}) {
    EXPECT_EQ(check_mjpeg(std::span(j).first(keep)), FrameProblem::kNoEoi) << "kept " << keep;
  }
}

TEST(MjpegStream, InjectedStreamIsCountedAndSkipped) {
  const auto good = mini_jpeg();
  auto corrupt_start = good;
  corrupt_start[0] = 0x00;
  const std::vector<uint8_t> zero_length;
  auto no_eoi = good;
  no_eoi.resize(good.size() - 2);
  no_eoi.insert(no_eoi.end(), 64, 0x00);  // padded, but the EOI is missing
  auto padded = good;
  padded.insert(padded.end(), 3000, 0x00);  // a good frame with UVC padding

  struct Buffer {
    const std::vector<uint8_t>* bytes;
    size_t keep;
    bool flagged;
  };
  const Buffer stream[] = {
      {&good, good.size(), false},     {&corrupt_start, good.size(), false},
      {&good, good.size() / 2, false}, {&zero_length, 0, false},
      {&no_eoi, no_eoi.size(), false}, {&padded, padded.size(), false},
      {&good, good.size(), true},  // the driver flagged it (e.g. a USB transfer error)
      {&good, good.size(), false},
  };
  SourceStats stats;
  FrameAccounting acc(stats);
  acc.reset_stream(0);
  const image::FrameFormat mjpeg{image::PixelFormat::kMjpeg, 3280, 2464, 0};
  std::vector<uint64_t> delivered;
  uint32_t seq = 0;
  for (const Buffer& b : stream) {
    const RawFrame raw{std::span(*b.bytes).first(b.keep), seq++, 1'000'000'000 + seq * 40'000'000LL,
                       b.flagged};
    if (acc.admit(raw, mjpeg) == Admission::kDeliverable) {
      acc.count_delivered();
      delivered.push_back(acc.sequence());
    }
  }
  EXPECT_EQ(delivered, (std::vector<uint64_t>{0, 5, 7}));
  EXPECT_EQ(stats.bad_mjpeg, 3u);  // corrupt start, truncated, EOI missing
  EXPECT_EQ(stats.empty, 1u);
  EXPECT_EQ(stats.flagged_error, 1u);
  EXPECT_EQ(stats.dropped, 0u);  // bad frames are counted as bad, not as lost
  EXPECT_NEAR(stats.measured_fps, 25.0, 1e-6);
}

}  // namespace
}  // namespace tlvlink::capture
