// The V4L2 source without a camera: configuration errors naming the field, a clear error when
// the device is absent or not a camera, and an outage that waits instead of spinning.
#include "tlvlink/capture/v4l2_source.h"

#include <time.h>

#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "support/temp_dir.h"

namespace tlvlink::capture {
namespace {

V4l2Config mini_config() {
  V4l2Config c;
  c.label = "mini-left";
  c.device = parse_device_selector("usb:0c45:636d:2BDF-Q7KX").value();
  c.format = image::PixelFormat::kMjpeg;
  c.width = 3280;
  c.height = 2464;
  c.fps = 25;
  return c;
}

std::string message_of(const V4l2Config& c) {
  auto s = make_v4l2_source(c);
  return s.ok() ? "" : s.error().message();
}

double cpu_seconds() {
  timespec ts{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

TEST(V4l2Config, ErrorsNameTheField) {
  EXPECT_EQ(message_of(mini_config()), "");
  auto c = mini_config();
  c.buffers = 1;
  EXPECT_NE(message_of(c).find("mini-left: buffers 1: must be 2..4"), std::string::npos)
      << message_of(c);
  c = mini_config();
  c.buffers = 5;
  EXPECT_NE(message_of(c).find("buffers 5"), std::string::npos);
  c = mini_config();
  c.width = 0;
  EXPECT_NE(message_of(c).find("size 0x2464"), std::string::npos);
  c = mini_config();
  c.warmup_frames = kMaxWarmupFrames + 1;
  EXPECT_NE(message_of(c).find("warmup_frames 121"), std::string::npos);
  c = mini_config();
  c.watchdog_ms = 10;
  EXPECT_NE(message_of(c).find("watchdog_ms 10"), std::string::npos);
  c = mini_config();
  c.backoff_initial_ms = 5000;
  c.backoff_max_ms = 1000;
  EXPECT_NE(message_of(c).find("backoff 5000..1000 ms"), std::string::npos);
  c = mini_config();
  c.device = DeviceSelector();
  EXPECT_NE(message_of(c).find("device: no USB id or path"), std::string::npos);
  c = mini_config();
  c.fps = -1;
  EXPECT_NE(message_of(c).find("fps -1.000"), std::string::npos);
}

TEST(V4l2Source, NextBeforeStartIsAnError) {
  auto src = make_v4l2_source(mini_config());
  ASSERT_TRUE(src.ok());
  auto f = (*src)->next(0);
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.error().code(), ErrorCode::kInvalidState);
  (*src)->stop();  // idempotent, nothing open
  (*src)->release();
  EXPECT_STREQ((*src)->name(), "mini-left (usb 0c45:636d serial 2BDF-Q7KX)");
}

TEST(V4l2Source, AbsentDeviceIsAClearError) {
  testing::TempDir empty("capture_nodev");
  auto c = mini_config();
  c.roots.sysfs = empty.path();
  c.roots.dev = empty.path();
  auto src = make_v4l2_source(c);
  ASSERT_TRUE(src.ok());
  Status s = (*src)->start();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kCaptureNoDevice);
  EXPECT_NE(
      std::string(s.error().message()).find("no camera matches usb 0c45:636d serial 2BDF-Q7KX"),
      std::string::npos)
      << s.error().message();
  EXPECT_FALSE((*src)->stats().connected);
}

TEST(V4l2Source, NotACameraIsAClearError) {
  auto c = mini_config();
  c.device = parse_device_selector("/dev/null").value();
  auto src = make_v4l2_source(c);
  Status s = (*src)->start();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kCaptureNotCamera);
}

// The device is gone: every next() waits its timeout (no spinning), reopen attempts follow the
// doubling backoff, and the outage is reported with its duration.
TEST(V4l2Source, OutageWaitsAndBacksOffWithoutSpinning) {
  testing::TempDir empty("capture_outage");
  auto c = mini_config();
  c.roots.sysfs = empty.path();
  c.roots.dev = empty.path();
  c.wait_for_device = true;
  c.backoff_initial_ms = 20;
  c.backoff_max_ms = 160;
  auto src = make_v4l2_source(c);
  ASSERT_TRUE((*src)->start().ok());

  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = cpu_seconds();
  constexpr int kCalls = 12;
  constexpr int kTimeoutMs = 100;
  for (int i = 0; i < kCalls; ++i) {
    const auto c0 = std::chrono::steady_clock::now();
    auto f = (*src)->next(kTimeoutMs);
    const auto ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - c0).count();
    ASSERT_FALSE(f.ok());
    EXPECT_EQ(f.error().code(), ErrorCode::kCaptureDisconnected);
    EXPECT_GE(ms, kTimeoutMs - 1) << "returned early: a caller's loop would spin";
    EXPECT_LE(ms, kTimeoutMs + 250)
        << "blocked far longer than its timeout";  // slack: a loaded 2-core CI
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = cpu_seconds() - cpu0;
  const SourceStats& st = (*src)->stats();
  // Attempts at 0, 20, 60, 140, 300 ms, then every 160 ms: about 10 in 1.2 s. The bound allows
  // scheduling slack but not a retry per call or a busy loop.
  EXPECT_GE(st.reconnect_attempts, 5u);
  EXPECT_LE(st.reconnect_attempts, 4 + static_cast<uint64_t>(wall * 1000 / c.backoff_max_ms) + 2);
  EXPECT_LT(cpu, 0.1 * wall) << "cpu " << cpu << " s over " << wall << " s";
  EXPECT_GE(st.outage_ns, static_cast<int64_t>(wall * 0.9e9));
  EXPECT_EQ(st.delivered, 0u);
  EXPECT_FALSE(st.connected);
  auto last = (*src)->next(0);
  EXPECT_NE(std::string(last.error().message()).find("reopen attempts failed"), std::string::npos)
      << last.error().message();
  EXPECT_NE(std::string(last.error().message()).find("no camera matches"), std::string::npos);
  (*src)->stop();
  std::printf("note: outage: %llu reopen attempts in %.2f s, cpu %.4f s\n",
              static_cast<unsigned long long>(st.reconnect_attempts), wall, cpu);
}

TEST(V4l2Source, ZeroTimeoutReturnsAtOnceWhileDisconnected) {
  testing::TempDir empty("capture_zero");
  auto c = mini_config();
  c.roots.sysfs = empty.path();
  c.roots.dev = empty.path();
  c.wait_for_device = true;
  auto src = make_v4l2_source(c);
  ASSERT_TRUE((*src)->start().ok());
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 100; ++i) EXPECT_FALSE((*src)->next(0).ok());
  const auto ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(ms, 200);
  // Only the first call was due for an attempt (the next is backoff_initial_ms later).
  EXPECT_LE((*src)->stats().reconnect_attempts, 2u);
}

}  // namespace
}  // namespace tlvlink::capture
