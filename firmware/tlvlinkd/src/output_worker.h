#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "output_worker.h is internal to firmware/tlvlinkd"
#endif
// The output thread: writes every queued record, measures per-stage latency (buffer timestamp to
// written), and every status interval writes a stats record and (optionally) a live status line;
// at the end a summary. It owns the latency statistics; the other threads' counters it reads
// through their snapshots.

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "capture_worker.h"
#include "frame_images.h"
#include "inference_worker.h"
#include "output_queue.h"
#include "output_sink.h"
#include "run_totals.h"
#include "tlvlink/pipeline/latency_stats.h"
#include "tlvlink/stream/names.h"

namespace tlvlink::daemon::internal {

using stream::OutputNames;

class OutputWorker {
 public:
  // Borrows the sinks, the names and the rest for its lifetime.
  OutputWorker(std::vector<OutputSink*> sinks, const OutputNames& names, OutputQueue& queue,
               const std::vector<std::unique_ptr<CaptureWorker>>& captures,
               const InferenceWorker& inference, std::vector<FrameRing*> rings,
               int32_t status_interval_ms, bool status_line, const std::atomic<bool>& stop);
  void run();  // returns when stop is set and the queue is drained
  // The FrameImages' counts go into the totals (borrowed; nullptr: off). Before run().
  void set_frame_images(const FrameImages* images) { images_ = images; }

  RunTotals totals() const;     // after run() returned
  bool outputs_closed() const;  // every output's reader left (a closed pipe): nothing to do
  void print_summary(std::FILE* out) const;

 private:
  void account(const pipeline::FramePrediction& p, int64_t written_ns);
  void report(int64_t now_ns, bool final);
  void status_line(int64_t now_ns);
  RunTotals collect(int64_t now_ns) const;

  std::vector<OutputSink*> sinks_;
  const OutputNames& names_;
  OutputQueue& queue_;
  const std::vector<std::unique_ptr<CaptureWorker>>& captures_;
  const InferenceWorker& inference_;
  std::vector<FrameRing*> rings_;
  int32_t interval_ms_;
  bool status_line_;
  const std::atomic<bool>& stop_;
  std::array<pipeline::LatencyStats, kStages> latency_;
  std::vector<pipeline::FramePrediction> last_;  // per sensor, for the status line
  uint64_t grasps_ = 0, grasps_not_computed_ = 0;
  float last_grasp_p_ = -1;
  int64_t start_ns_ = 0, start_cpu_ns_ = 0;
  clockid_t cpu_clock_ = CLOCK_THREAD_CPUTIME_ID;
  const FrameImages* images_ = nullptr;
  RunTotals final_;
};

}  // namespace tlvlink::daemon::internal
