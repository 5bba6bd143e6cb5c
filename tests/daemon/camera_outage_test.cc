// A camera that is gone, seen from the daemon: the capture thread must not spin even when its
// source returns errors at once (the failure of issue 15's HIL run: a V4L2 source that reported
// its outage again on every call, ~1 µs apart), and the outage counters reach the JSON lines.
#include <atomic>
#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/temp_dir.h"
#include "tlvlink/daemon/config.h"
#include "tlvlink/daemon/session.h"

namespace tlvlink::daemon {
namespace {

constexpr const char* kModel = TLVLINK_SOURCE_DIR "/firmware/models/touch-tiny-int8.tlvm";

// Gone since start and failing fast: every next() returns capture.disconnected at once.
class GoneSource final : public capture::FrameSource {
 public:
  explicit GoneSource(std::atomic<uint64_t>& calls) : calls_(calls) {
    stats_.disconnects = 1;  // lost once, never back
  }
  Status start() override { return {}; }
  Result<capture::CapturedFrame> next(int32_t) override {
    ++calls_;
    ++stats_.reconnect_attempts;
    stats_.outage_ns += 1'000'000;
    return Error(ErrorCode::kCaptureDisconnected, "gone: no such device");
  }
  void release() override {}
  void stop() override {}
  const image::FrameFormat& format() const override { return format_; }
  const capture::SourceStats& stats() const override { return stats_; }
  const char* name() const override { return "gone"; }

 private:
  std::atomic<uint64_t>& calls_;
  image::FrameFormat format_{image::PixelFormat::kYuyv, 640, 480, 1280};
  capture::SourceStats stats_;
};

TEST(DaemonCameraOutage, FastFailingSourceIsPacedAndItsOutageReported) {
  testing::TempDir dir;
  const std::string out = dir.path() + "/out.jsonl";
  auto config = parse_config(std::string("model = \"") + kModel +
                                 "\"\n"
                                 "output = \"jsonl:" +
                                 out +
                                 "\"\n"
                                 "status_interval_ms = 200\n"
                                 "[[sensor]]\nname = \"A\"\nmodel = \"digit-640x480\"\n"
                                 "source = \"replay\"\ndevice = \"memory\"\n",
                             "test.toml");
  ASSERT_TRUE(config.ok()) << config.error().message();
  std::atomic<uint64_t> calls{0};
  std::vector<std::unique_ptr<capture::FrameSource>> sources;
  sources.push_back(std::make_unique<GoneSource>(calls));
  auto session = Session::start_with_sources(*config, std::move(sources));
  ASSERT_TRUE(session.ok()) << session.error().message();
  const auto t0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  (*session)->stop();
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // One call per 100 ms poll period; without pacing this is in the hundreds of thousands.
  EXPECT_LE(calls.load(), static_cast<uint64_t>(s * 10) + 3) << "in " << s << " s";
  EXPECT_GE(calls.load(), 5u);

  std::ifstream in(out);
  std::string line, events;
  bool summary = false;
  while (std::getline(in, line)) {
    const auto j = nlohmann::json::parse(line);
    if (j.at("type") == "error") events += j.at("text").get<std::string>() + "\n";
    if (j.at("type") != "stats" || !j.at("final")) continue;
    summary = true;
    const auto& cam = j.at("daemon").at("camera");
    EXPECT_EQ(cam.at("disconnects").at(0), 1) << line;
    EXPECT_EQ(cam.at("reconnects").at(0), 0) << line;
    EXPECT_EQ(cam.at("reopen_failures").at(0), calls.load()) << line;
    EXPECT_GT(cam.at("outage_s").at(0).get<double>(), 0.0) << line;
  }
  EXPECT_TRUE(summary);
  // The outage is one event, not one per call.
  EXPECT_NE(events.find("camera lost: gone: no such device"), std::string::npos) << events;
  EXPECT_EQ(events.find("camera lost"), events.rfind("camera lost")) << events;
}

}  // namespace
}  // namespace tlvlink::daemon
