// The camera of the hardware-in-the-loop run (tests/hil) lost and found again: the source reads
// vivid's HDMI output->capture loop through a symlink (the udev rule's stand-in, present only
// while the loop is set up), holds a frame as a consumer does while it decodes, and vivid is
// unplugged (platform unbind), unloaded and loaded again. The held frame's requeue is the first
// call that fails (VIDIOC_QBUF: ENODEV). The source must count one outage, wait out its backoff
// without spinning, reopen the node the link points at once the loop is set up again, and
// deliver looped frames. These change the system's devices: rig only.
#include <time.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>

#include "tlvlink/capture/v4l2_source.h"
#include "vivid/loop_feeder.h"
#include "vivid/vivid_support.h"

namespace tlvlink::capture {
namespace {

constexpr char kLink[] = "/tmp/vivid-loop-cam";

using vivid::cpu_seconds;
using vivid::write_sysfs;

class VividLoopReload : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto reason = vivid::absent_reason(); !reason.empty()) GTEST_SKIP() << reason;
    if (!vivid::in_rig())
      GTEST_SKIP() << "unbinds and reloads vivid: runs only in the board rig (TLVLINK_RIG=1)";
    if (vivid::find_nodes()->output.empty())
      GTEST_SKIP() << "vivid has no output node (load it with node_types=0x101)";
  }
  void TearDown() override {
    src.reset();
    feeder.reset();
    ::unlink(kLink);
    // Leave vivid as the next tests expect it: loaded, webcam input.
    if (!vivid::find_nodes()) (void)std::system("rig rig_vivid_unload; rig rig_vivid_load");
    if (auto n = vivid::find_nodes()) (void)vivid::select_input(n->capture, 0);
  }

  // The loop set up (output streaming, HDMI timings on both sides), then the link to the capture
  // node: the order of tests/hil's feeder and its link.
  void loop_up() {
    const auto nodes = vivid::find_nodes();
    ASSERT_TRUE(nodes.has_value());
    auto f = vivid::LoopFeeder::start(*nodes, image::PixelFormat::kYuyv, vivid::Pattern::kIndexed);
    ASSERT_TRUE(f.ok()) << f.error().message();
    feeder = std::move(*f);
    feeder->feed_every(40);
    ::unlink(kLink);
    ASSERT_EQ(::symlink(nodes->capture.c_str(), kLink), 0);
  }

  // A looped frame (the index pattern of what was fed), not vivid's own test pattern.
  static bool looped(const CapturedFrame& f) {
    uint32_t index = 0;
    return vivid::frame_index(f.bytes, index);
  }

  std::unique_ptr<vivid::LoopFeeder> feeder;
  std::unique_ptr<V4l2Source> src;
};

TEST_F(VividLoopReload, HeldFrameAcrossUnplugAndModuleReloadThroughALink) {
  loop_up();
  ASSERT_FALSE(HasFatalFailure());
  V4l2Config cfg = vivid::capture_config({kLink, ""}, image::PixelFormat::kYuyv, vivid::kLoopWidth,
                                         vivid::kLoopHeight, 0);
  cfg.controls = parse_controls("osd_text_mode=2, loop_video=1").value();
  cfg.warmup_frames = 2;
  auto made = make_v4l2_source(cfg);
  ASSERT_TRUE(made.ok());
  src = std::move(*made);
  Status st = src->start();
  ASSERT_TRUE(st.ok()) << st.error().message();
  int looped_before = 0;
  for (int i = 0; i < 30 && looped_before < 3; ++i) {
    auto f = src->next(3000);
    ASSERT_TRUE(f.ok()) << f.error().message();
    looped_before += looped(*f) ? 1 : 0;
    src->release();
  }
  ASSERT_EQ(looped_before, 3) << "the loop did not deliver before the fault";

  // A frame held (being decoded) while the camera is unplugged: its requeue fails.
  auto held = src->next(3000);
  ASSERT_TRUE(held.ok()) << held.error().message();
  ::unlink(kLink);
  ASSERT_TRUE(write_sysfs("/sys/bus/platform/drivers/vivid/unbind", "vivid.0"));
  feeder.reset();  // the feeder's node closes too, or the module cannot go
  src->release();

  // The outage is reported by the next call (at once: the device is already known gone)...
  auto lost = src->next(100);
  ASSERT_FALSE(lost.ok());
  EXPECT_EQ(lost.error().code(), ErrorCode::kCaptureDisconnected) << lost.error().message();
  std::printf("note: outage reported: %s\n", lost.error().message());
  // ...then one disconnect only, and every call waits its timeout (the capture thread's loop).
  constexpr int kCalls = 10;
  const double cpu0 = cpu_seconds();
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < kCalls; ++i) {
    auto f = src->next(100);
    ASSERT_FALSE(f.ok());
    EXPECT_EQ(f.error().code(), ErrorCode::kCaptureDisconnected) << f.error().message();
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = cpu_seconds() - cpu0;
  std::printf("note: gone: %d calls in %.2f s, cpu %.3f s, %llu disconnects\n", kCalls, wall, cpu,
              static_cast<unsigned long long>(src->stats().disconnects));
  EXPECT_GE(wall, kCalls * 0.095) << "next() returned early: a caller's loop spins";
  EXPECT_LT(cpu, 0.25 * wall);
  EXPECT_EQ(src->stats().disconnects, 1u) << "one unplug is one outage";
  EXPECT_FALSE(src->stats().connected);

  // Module out and in again (the source closed the node); the link reappears once the loop is
  // set up, as the HIL feeder does it.
  ASSERT_EQ(std::system("rig rig_vivid_unload"), 0) << "the source still holds the node open";
  ASSERT_EQ(std::system("rig rig_vivid_load"), 0);
  const auto reload = std::chrono::steady_clock::now();
  loop_up();
  ASSERT_FALSE(HasFatalFailure());

  int looped_after = 0;
  double back_ms = -1;
  for (int i = 0; i < 100 && looped_after < 3; ++i) {  // at most ~10 s of 100 ms calls
    auto f = src->next(100);
    if (!f.ok()) continue;
    if (looped(*f)) {
      if (looped_after++ == 0) {
        back_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - reload)
                .count();
        EXPECT_LE(f->sequence, 8u) << "sequences restart at 0 after a reopen";
      }
    }
    src->release();
  }
  const SourceStats& s = src->stats();
  EXPECT_EQ(looped_after, 3) << "no looped frame within 10 s of the reload: disconnects "
                             << s.disconnects << ", reconnects " << s.reconnects
                             << ", reopen attempts " << s.reconnect_attempts;
  EXPECT_TRUE(s.connected);
  EXPECT_EQ(s.disconnects, 1u);
  EXPECT_EQ(s.reconnects, 1u);
  EXPECT_EQ(src->device().path, vivid::find_nodes()->capture) << "the link's new target";
  std::printf(
      "note: looped frames again %.0f ms after the reload; %llu reopen attempts, outage %.2f s\n",
      back_ms, static_cast<unsigned long long>(s.reconnect_attempts),
      static_cast<double>(s.outage_ns) / 1e9);
}

}  // namespace
}  // namespace tlvlink::capture
