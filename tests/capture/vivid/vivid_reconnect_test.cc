// The device goes away and comes back while the source streams: vivid unbound from its
// platform device and bound again (an unplug/replug), and vivid's own "Disconnect" followed by a
// module unload and reload. The source reports the outage, waits without spinning, reconnects by
// itself and applies its controls again. These change the system's devices: rig only.
#include <time.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "tlvlink/capture/v4l2_source.h"
#include "vivid/vivid_support.h"

namespace tlvlink::capture {
namespace {

using vivid::cpu_seconds;
using vivid::write_sysfs;

class VividReconnect : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto reason = vivid::absent_reason(); !reason.empty()) GTEST_SKIP() << reason;
    if (!vivid::in_rig())
      GTEST_SKIP() << "unbinds and reloads vivid: runs only in the board rig (TLVLINK_RIG=1)";
    nodes = *vivid::find_nodes();
    ASSERT_EQ(vivid::select_input(nodes.capture, 0), 0);
  }

  std::unique_ptr<V4l2Source> streaming(const char* controls) {
    auto cfg = vivid::capture_config(nodes, image::PixelFormat::kYuyv, 320, 180, 25);
    cfg.controls = parse_controls(controls).value();
    auto src = make_v4l2_source(cfg);
    EXPECT_TRUE(src.ok());
    Status st = (*src)->start();
    EXPECT_TRUE(st.ok()) << st.error().message();
    for (int i = 0; i < 3; ++i) {
      auto f = (*src)->next(3000);
      EXPECT_TRUE(f.ok());
      (*src)->release();
    }
    return std::move(*src);
  }

  // next() until the outage shows; returns how long that took.
  double until_disconnected(V4l2Source& src) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < 50; ++i) {
      auto f = src.next(100);
      if (f.ok()) {
        src.release();
        continue;
      }
      if (f.error().code() == ErrorCode::kCaptureDisconnected) {
        std::printf("note: outage reported: %s\n", f.error().message());
        break;
      }
    }
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }

  // While the device is gone: every call waits its timeout; little CPU is used.
  void gone_for(V4l2Source& src, int calls) {
    const double cpu0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < calls; ++i) {
      auto f = src.next(100);
      ASSERT_FALSE(f.ok());
      EXPECT_EQ(f.error().code(), ErrorCode::kCaptureDisconnected) << f.error().message();
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = cpu_seconds() - cpu0;
    std::printf("note: gone: %d calls in %.2f s, cpu %.3f s, %llu reopen attempts so far\n", calls,
                wall, cpu, static_cast<unsigned long long>(src.stats().reconnect_attempts));
    EXPECT_GE(wall, calls * 0.095);
    EXPECT_LT(cpu, 0.25 * wall);
  }

  // next() until frames flow again; returns the milliseconds that took.
  double until_frames(V4l2Source& src) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < 100; ++i) {
      auto f = src.next(100);
      if (f.ok()) {
        EXPECT_LE(f->sequence, 3u) << "sequences restart at 0 after a reopen";
        src.release();
        break;
      }
    }
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }

  vivid::Nodes nodes;
};

TEST_F(VividReconnect, UnbindAndRebind) {
  auto src = streaming("osd_text_mode=2, brightness=200");
  ASSERT_NE(src, nullptr);
  ASSERT_TRUE(write_sysfs("/sys/bus/platform/drivers/vivid/unbind", "vivid.0"));
  const double detect_ms = until_disconnected(*src);
  EXPECT_FALSE(src->stats().connected);
  EXPECT_EQ(src->stats().disconnects, 1u);
  gone_for(*src, 8);
  ASSERT_TRUE(write_sysfs("/sys/bus/platform/drivers/vivid/bind", "vivid.0"));
  auto back = vivid::find_nodes();
  ASSERT_TRUE(back.has_value());
  int64_t brightness = -1;
  ASSERT_EQ(vivid::get_control(back->capture, "brightness", brightness), 0);
  EXPECT_EQ(brightness, 128) << "a rebound vivid starts from its defaults";
  const double back_ms = until_frames(*src);
  ASSERT_TRUE(src->stats().connected);
  EXPECT_EQ(src->stats().reconnects, 1u);
  ASSERT_EQ(vivid::get_control(back->capture, "brightness", brightness), 0);
  EXPECT_EQ(brightness, 200) << "controls are applied again after a reconnect";
  std::printf(
      "note: unbind detected in %.0f ms; frames again %.0f ms after rebind; outage %.2f s\n",
      detect_ms, back_ms, static_cast<double>(src->stats().outage_ns) / 1e9);
}

TEST_F(VividReconnect, DisconnectThenModuleReload) {
  auto src = streaming("osd_text_mode=2, brightness=60");
  ASSERT_NE(src, nullptr);
  ASSERT_EQ(vivid::set_control(nodes.capture, "disconnect", 1), 0);  // vivid's simulated unplug
  const double detect_ms = until_disconnected(*src);
  ASSERT_FALSE(src->stats().connected);
  // The source closed the node, so the module can go.
  ASSERT_EQ(std::system("rig rig_vivid_unload"), 0);
  gone_for(*src, 5);
  ASSERT_EQ(std::system("rig rig_vivid_load"), 0);
  const double back_ms = until_frames(*src);
  ASSERT_TRUE(src->stats().connected);
  EXPECT_GE(src->stats().reconnects, 1u);
  int64_t brightness = -1;
  ASSERT_EQ(vivid::get_control(vivid::find_nodes()->capture, "brightness", brightness), 0);
  EXPECT_EQ(brightness, 60);
  std::printf(
      "note: disconnect detected in %.0f ms; frames %.0f ms after the reload; %llu reopen "
      "attempts\n",
      detect_ms, back_ms, static_cast<unsigned long long>(src->stats().reconnect_attempts));
}

}  // namespace
}  // namespace tlvlink::capture
