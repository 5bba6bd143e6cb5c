#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "run_totals.h is internal to firmware/tlvlinkd"
#endif
// What a running session reports every status interval and at the end: counts, drops by cause,
// per-stage latency percentiles, CPU, memory. Fixed-size (collected without allocating).

#include <array>
#include <cstdint>

#include "tlvlink/pipeline/predictions.h"

namespace tlvlink::daemon::internal {

// Latency stages reported (FrameTimes differences), named alike in the JSON lines, the stats and
// the stream's stage_ns: dequeue = capture -> dequeued, decode = dequeued -> decoded, queue =
// decoded -> contact decision (the wait for the inference thread; the gate's own few
// microseconds have no timestamp of their own and are in it), then preprocess, encoder, heads,
// write (-> the output stage took it) and total (capture -> written).
enum Stage : int32_t {
  kDequeue = 0,
  kDecode,
  kQueueWait,
  kPreprocess,
  kEncoder,
  kHeads,
  kWrite,
  kTotal,
  kStages
};
const char* stage_name(int32_t stage);

struct RunTotals {
  int64_t t_ns = 0;
  uint64_t frames = 0, encoded = 0, gated = 0, grasps = 0, grasps_not_computed = 0;
  uint64_t drops_stale = 0, drops_sequence = 0, drops_queue = 0, drops_output = 0;
  uint64_t bad_frames = 0, decode_errors = 0, inference_errors = 0, write_errors = 0;
  double seconds = 0, process_cpu_pct = 0;
  std::array<double, kStages> p50_ms{}, p99_ms{}, max_ms{};
  int32_t sensors = 0;
  std::array<double, pipeline::kMaxSensors> sensor_cpu_pct{}, sensor_fps{};
  std::array<uint64_t, pipeline::kMaxSensors> sensor_frames{}, sensor_encoded{}, sensor_gated{};
  // Camera outages per sensor (capture::SourceStats): begun, ended by a reopen, reopen attempts
  // that failed, time without a camera.
  std::array<uint64_t, pipeline::kMaxSensors> sensor_disconnects{}, sensor_reconnects{},
      sensor_reopen_failures{};
  std::array<double, pipeline::kMaxSensors> sensor_outage_s{};
  double inference_cpu_pct = 0, output_cpu_pct = 0;
  bool frame_images = false;                      // configured on
  uint64_t images_sent = 0, drops_image = 0;      // FrameImages posted; not sent (image_busy)
  double image_copy_us = 0, image_encode_ms = 0;  // per image: inference thread, encoder thread
  int64_t peak_rss_kb = 0;
};

}  // namespace tlvlink::daemon::internal
