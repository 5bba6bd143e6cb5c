#pragma once
// vivid's output->capture loop as a frame injector: our frames go into the output node and come
// back out of the capture node, which the V4L2 source reads like a camera. Both sides HDMI
// (capture input 3, output 1) with the same DV timings (640x480p59.94), same format and size.
// The output is queued and streaming before the capture starts (vivid needs that to loop).
//
// Frames are generated from their index (frame_pattern), so a captured frame identifies itself
// and can be compared bit for bit without storing what was sent.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <thread>

#include "tlvlink/error.h"
#include "tlvlink/image/pixel_format.h"
#include "vivid/vivid_support.h"

namespace tlvlink::capture::vivid {

inline constexpr int32_t kLoopWidth = 640, kLoopHeight = 480;

enum class Pattern : uint8_t { kIndexed, kAllZero, kAllMax, kNoise };

// Fills a frame: kIndexed writes the index into the first 8 bytes (little endian, twice: index
// and ~index) and a per-index hash elsewhere; the others are the extreme frames (all 0, all 255,
// seeded noise) with the index in the first 8 bytes too.
void frame_pattern(Pattern pattern, uint32_t index, std::span<uint8_t> out);
// The index a frame carries, or false if its header is not a valid one.
bool frame_index(std::span<const uint8_t> frame, uint32_t& index);

// Writes frame `index` (the index-th frame fed, from 0) into a buffer of the output's frame size.
using FrameFill = std::function<void(uint32_t index, std::span<uint8_t> out)>;

class LoopFeeder {
 public:
  // Configures both nodes and starts the output stream with frame 0 queued.
  static Result<std::unique_ptr<LoopFeeder>> start(const Nodes& nodes, image::PixelFormat format,
                                                   Pattern pattern);
  // The same with frames from elsewhere (tests/hil feeds simulated GelSight frames).
  static Result<std::unique_ptr<LoopFeeder>> start(const Nodes& nodes, image::PixelFormat format,
                                                   FrameFill fill);
  ~LoopFeeder();
  LoopFeeder(const LoopFeeder&) = delete;
  LoopFeeder& operator=(const LoopFeeder&) = delete;

  // Queues a new frame every interval_ms from a thread (frame i+1 after frame i); 0 pauses (the
  // output keeps showing the last frame queued).
  void feed_every(int32_t interval_ms);
  // Stops the output stream (the capture side falls back to vivid's test pattern).
  void stop_output();
  uint32_t frames_queued() const { return next_index_.load(); }
  const image::FrameFormat& format() const { return format_; }

 private:
  LoopFeeder() = default;
  void run();
  bool queue_next();

  int fd_ = -1;
  image::FrameFormat format_;
  FrameFill fill_;
  uint8_t* buffers_[4] = {};
  size_t lengths_[4] = {};
  uint32_t count_ = 0;
  std::atomic<uint32_t> next_index_{0};
  std::atomic<int32_t> interval_ms_{0};
  std::atomic<bool> quit_{false};
  std::thread thread_;
};

}  // namespace tlvlink::capture::vivid
