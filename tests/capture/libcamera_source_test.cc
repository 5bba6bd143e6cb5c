// The libcamera source where no libcamera camera exists (Debian's kernels have no vimc): it
// builds, enumerates, reports "no camera" clearly, and runs its frame path on injected buffers.
#include "tlvlink/capture/libcamera_source.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

namespace tlvlink::capture {
namespace {

LibcameraConfig yuyv_config() {
  LibcameraConfig c;
  c.label = "pi-gel";
  c.format = image::PixelFormat::kYuyv;
  c.width = 64;
  c.height = 48;
  return c;
}

TEST(Libcamera, VersionAndEnumeration) {
  EXPECT_FALSE(libcamera_version().empty());
  auto cams = list_libcamera_cameras();
  ASSERT_TRUE(cams.ok()) << cams.error().message();
  std::printf("note: libcamera %s: %zu cameras\n", libcamera_version().c_str(), cams->size());
  for (const auto& c : *cams) std::printf("note: camera %s '%s'\n", c.id.c_str(), c.model.c_str());
}

TEST(Libcamera, NoCameraIsAClearError) {
  auto cams = list_libcamera_cameras();
  ASSERT_TRUE(cams.ok());
  if (!cams->empty())
    GTEST_SKIP() << "a libcamera camera is present (" << (*cams)[0].id
                 << "); this checks the no-camera error";
  auto src = make_libcamera_source(yuyv_config());
  ASSERT_TRUE(src.ok());
  Status s = (*src)->start();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kCaptureNoDevice);
  EXPECT_NE(std::string(s.error().message()).find("pi-gel: libcamera v0.0.3 found no camera"),
            std::string::npos)
      << s.error().message();
  EXPECT_FALSE((*src)->next(0).ok());  // not started
}

TEST(Libcamera, ConfigErrorsNameTheField) {
  auto c = yuyv_config();
  c.buffers = 9;
  auto s = make_libcamera_source(c);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(std::string(s.error().message()).find("pi-gel: buffers 9"), std::string::npos);
  c = yuyv_config();
  c.height = 0;
  EXPECT_FALSE(make_libcamera_source(c).ok());
}

class InjectedBuffers : public ::testing::Test {
 protected:
  void SetUp() override {
    for (auto& m : memory) m.assign(64 * 48 * 2, 0x80);
    std::vector<std::span<const uint8_t>> spans;
    for (auto& m : memory) spans.emplace_back(m);
    auto s = make_libcamera_source_for_test(yuyv_config(), spans);
    ASSERT_TRUE(s.ok()) << s.error().message();
    src = std::move(*s);
    ASSERT_TRUE(src->start().ok());
  }
  static LibcameraCompletion done(uint32_t buffer, uint32_t seq, uint32_t bytes = 64 * 48 * 2) {
    LibcameraCompletion c;
    c.buffer = buffer;
    c.sequence = seq;
    c.timestamp_ns = 1'000'000'000 + static_cast<int64_t>(seq) * 16'666'667;
    c.bytesused = bytes;
    return c;
  }
  std::vector<uint8_t> memory[4];
  std::unique_ptr<LibcameraSource> src;
};

TEST_F(InjectedBuffers, NewestFrameAndRequeue) {
  src->inject(done(0, 100));
  src->inject(done(1, 101));
  src->inject(done(2, 102));
  auto f = src->next(100);
  ASSERT_TRUE(f.ok()) << f.error().message();
  EXPECT_EQ(f->sequence, 2u);
  EXPECT_EQ(f->skipped_before, 2u);
  EXPECT_EQ(f->bytes.data(), memory[2].data());
  EXPECT_EQ(f->bytes.size(), memory[2].size());
  EXPECT_EQ(f->timestamp_ns, 1'000'000'000 + 102 * 16'666'667LL);
  EXPECT_EQ(src->requeued(), 2u);  // the two older ones went straight back
  src->release();
  EXPECT_EQ(src->requeued(), 3u);
  EXPECT_EQ(src->stats().skipped_stale, 2u);
  EXPECT_NEAR(src->stats().measured_fps, 60.0, 0.01);
}

TEST_F(InjectedBuffers, BadBuffersAreCountedAndSkipped) {
  auto flagged = done(0, 1);
  flagged.error = true;
  auto cancelled = done(1, 2);
  cancelled.cancelled = true;
  src->inject(flagged);
  src->inject(cancelled);
  src->inject(done(2, 3, 100));  // short
  src->inject(done(3, 4, 0));    // empty
  auto f = src->next(50);
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.error().code(), ErrorCode::kCaptureTimeout);
  const SourceStats& s = src->stats();
  EXPECT_EQ(s.flagged_error, 1u);
  EXPECT_EQ(s.short_frames, 1u);
  EXPECT_EQ(s.empty, 1u);
  EXPECT_EQ(s.timeouts, 1u);
  EXPECT_EQ(src->requeued(), 3u);  // the cancelled one is the camera's to drop
  src->inject(done(0, 6));
  auto g = src->next(50);
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(s.dropped, 2u);  // 2 (cancelled: no frame) and 5 never came
}

TEST_F(InjectedBuffers, TruncatedMjpegIsSkipped) {
  auto c = yuyv_config();
  c.format = image::PixelFormat::kMjpeg;
  std::vector<uint8_t> jpeg = {0xFF, 0xD8, 0xFF, 0xE0, 0x00, 0x10, 0x01, 0x02, 0xFF, 0xD9};
  auto s = make_libcamera_source_for_test(c, {std::span<const uint8_t>(jpeg)});
  ASSERT_TRUE(s.ok());
  ASSERT_TRUE((*s)->start().ok());
  (*s)->inject(done(0, 0, 6));  // cut before the EOI
  EXPECT_FALSE((*s)->next(20).ok());
  EXPECT_EQ((*s)->stats().bad_mjpeg, 1u);
  (*s)->inject(done(0, 1, static_cast<uint32_t>(jpeg.size())));
  auto f = (*s)->next(20);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->bytes.size(), jpeg.size());
}

TEST_F(InjectedBuffers, CompletionFromAnotherThreadWakesNext) {
  std::thread producer([this] {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    src->inject(done(1, 7));
  });
  const auto t0 = std::chrono::steady_clock::now();
  auto f = src->next(2000);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  producer.join();
  ASSERT_TRUE(f.ok()) << f.error().message();
  EXPECT_LT(ms, 1000) << "next() waited for its timeout instead of the completion";
  EXPECT_GE(ms, 20);
}

}  // namespace
}  // namespace tlvlink::capture
