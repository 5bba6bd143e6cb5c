#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "capture_worker.h is internal to firmware/tlvlinkd"
#endif
// One sensor's capture thread: the newest frame from its source, decoded into the sensor's
// processed frame (the heaviest stage: an 8 MP MJPEG at 1/8 scale), handed to the inference
// thread through its FrameRing, and the camera buffer returned at once. Outages and bad frames
// become events; the loop never stops for them.

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "frame_ring.h"
#include "output_queue.h"
#include "tlvlink/capture/frame_source.h"
#include "tlvlink/image/frame_decoder.h"

namespace tlvlink::daemon::internal {

struct CaptureSnapshot {
  capture::SourceStats source;
  uint64_t decode_errors = 0;
  int64_t cpu_ns = 0;  // this thread's CPU time
};

class CaptureWorker {
 public:
  // Borrows ring, events and stop for its lifetime. The source has been started.
  CaptureWorker(int32_t index, std::string name, std::unique_ptr<capture::FrameSource> source,
                image::FrameDecoder decoder, FrameRing& ring, OutputQueue& events,
                const std::atomic<bool>& stop);
  void
  run();  // the thread body; returns when stop is set or a replay ended (the source is stopped)
  bool ended() const { return ended_.load(); }  // a replay played its last frame (or failed)
  // A replay that cannot go on (kFormat: e.g. no good frame in a whole pass): ended, in error.
  bool failed() const { return failed_.load(); }

  CaptureSnapshot snapshot() const;
  const std::string& name() const { return name_; }

 private:
  void event(bool error, const char* format, ...) __attribute__((format(printf, 3, 4)));
  void handle_error(const Error& e);

  int32_t index_;
  std::string name_;
  std::unique_ptr<capture::FrameSource> source_;
  image::FrameDecoder decoder_;
  FrameRing& ring_;
  OutputQueue& events_;
  const std::atomic<bool>& stop_;
  bool in_outage_ = false;
  int64_t last_decode_event_ns_ = 0;
  std::atomic<clockid_t> cpu_clock_{-1};
  std::atomic<bool> ended_{false}, failed_{false};
  std::atomic<int64_t> final_cpu_ns_{-1};  // set when run() returns (a dead thread has no clock)
  mutable std::mutex mutex_;
  CaptureSnapshot snapshot_;
};

}  // namespace tlvlink::daemon::internal
