#pragma once
// A FrameSource over frames held in memory, for daemon tests: cycles through them, paced at a
// frame rate (or as fast as asked), timestamps on CLOCK_MONOTONIC like a camera's. next()
// allocates nothing.

#include <chrono>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "tlvlink/capture/frame_source.h"
#include "tlvlink/clock.h"

namespace tlvlink::testing {

class MemorySource final : public capture::FrameSource {
 public:
  MemorySource(std::string name, image::FrameFormat format,
               std::vector<std::vector<uint8_t>> frames, double fps, int64_t phase_ns = 0)
      : name_(std::move(name)),
        format_(format),
        frames_(std::move(frames)),
        fps_(fps),
        phase_ns_(phase_ns) {}

  Status start() override {
    t0_ = now() + phase_ns_;
    stats_.connected = true;
    stats_.nominal_fps = fps_;
    return {};
  }
  Result<capture::CapturedFrame> next(int32_t timeout_ms) override {
    const int64_t period = fps_ > 0 ? static_cast<int64_t>(1e9 / fps_) : 0;
    const int64_t due = t0_ + static_cast<int64_t>(k_) * period;
    const int64_t wait = due - now();
    if (wait > static_cast<int64_t>(timeout_ms) * 1'000'000) {
      std::this_thread::sleep_for(std::chrono::milliseconds(timeout_ms));
      ++stats_.timeouts;
      return Error(ErrorCode::kCaptureTimeout, "memory source: no frame yet");
    }
    if (wait > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
    capture::CapturedFrame f;
    const std::vector<uint8_t>& bytes = frames_[k_ % frames_.size()];
    f.bytes = bytes;
    f.format = format_;
    f.sequence = k_;
    f.timestamp_ns = period > 0 ? due : now();
    ++k_;
    ++stats_.delivered;
    stats_.measured_fps = fps_;
    return f;
  }
  void release() override {}
  void stop() override { stats_.connected = false; }
  const image::FrameFormat& format() const override { return format_; }
  const capture::SourceStats& stats() const override { return stats_; }
  const char* name() const override { return name_.c_str(); }

 private:
  static int64_t now() { return board_clock_ns(); }
  std::string name_;
  image::FrameFormat format_;
  std::vector<std::vector<uint8_t>> frames_;
  double fps_;
  int64_t phase_ns_;
  int64_t t0_ = 0;
  uint64_t k_ = 0;
  capture::SourceStats stats_;
};

}  // namespace tlvlink::testing
