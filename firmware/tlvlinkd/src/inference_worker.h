#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "inference_worker.h is internal to firmware/tlvlinkd"
#endif
// The inference thread: takes decoded frames from every sensor's ring in capture-time order
// (each finger's frames stay in order for the grasp logic), runs the FrameProcessor on them and
// queues the predictions for output. Applies controller commands between frames.

#include <atomic>
#include <cstdint>
#include <vector>

#include "commands.h"
#include "frame_images.h"
#include "frame_ring.h"
#include "output_queue.h"
#include "tlvlink/pipeline/frame_processor.h"

namespace tlvlink::daemon::internal {

struct InferenceSnapshot {
  pipeline::ProcessorCounters counters;
  uint64_t errors = 0;
  int64_t cpu_ns = 0;
};

class InferenceWorker {
 public:
  // Borrows everything for its lifetime. max_frames 0: no limit; reaching it sets `limit_hit`.
  InferenceWorker(pipeline::FrameProcessor& processor, std::vector<FrameRing*> rings,
                  std::vector<pipeline::SensorSetup> setups, Doorbell& doorbell,
                  OutputQueue& output, CommandQueue& commands, const std::atomic<bool>& stop,
                  std::atomic<bool>& limit_hit, int64_t max_frames,
                  std::vector<ScriptedCommand> script = {});
  void run();  // returns when stop is set, after the frames already decoded are processed
  // FrameImages offered every processed frame (borrowed; nullptr: off). Before run().
  void set_frame_images(FrameImages* images) { images_ = images; }

  InferenceSnapshot snapshot() const;

 private:
  bool process_one();  // false when no frame is waiting
  void apply(const Command& c);
  void drain_grasps();

  pipeline::FrameProcessor& processor_;
  std::vector<FrameRing*> rings_;
  std::vector<pipeline::SensorSetup> setups_;  // the processed frames' geometry per ring
  Doorbell& doorbell_;
  OutputQueue& output_;
  CommandQueue& commands_;
  std::vector<ScriptedCommand> script_;  // ordered by sequence; given as their frames come
  size_t next_scripted_ = 0;
  const std::atomic<bool>& stop_;
  std::atomic<bool>& limit_hit_;
  int64_t max_frames_;
  std::atomic<clockid_t> cpu_clock_{-1};
  std::atomic<int64_t> final_cpu_ns_{-1};  // set when run() returns (a dead thread has no clock)
  std::atomic<uint64_t> errors_{0};
  mutable std::mutex mutex_;  // guards the counters copy
  pipeline::ProcessorCounters counters_;
  FrameImages* images_ = nullptr;
  pipeline::FramePrediction record_;  // reused: no per-frame construction on the stack churn
};

}  // namespace tlvlink::daemon::internal
