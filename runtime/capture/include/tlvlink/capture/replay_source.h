#pragma once
// A recorded raw stream (recording.h) played back behind the FrameSource interface, so the
// daemon, the pipeline and the tests run on exactly what a camera emitted.
//
// Realtime (the default) paces frames as the camera did: frame k is due at start + its recorded
// capture offset, next() waits for it (bounded by the timeout, like a camera's poll), and a
// consumer that falls behind gets the newest due frame with the older ones counted as
// skipped_stale, as the V4L2 source's newest-frame policy does. Timestamps are the due times on
// CLOCK_MONOTONIC, so latency measured from them means what it means for a camera. Without
// realtime, frames come as fast as they are asked for, none skipped, stamped with the same
// recorded timeline (start + offset): what runs on frame times (smoothing, grasp timing) sees the
// camera's pace at any speed, but a latency measured from them means nothing (it is negative
// while the replay runs ahead of the clock).
//
// Every frame goes through the same checks and counters as a camera's (frame_accounting.h): a
// frame whose CRC-32 does not match, a flagged or truncated one is counted and skipped. At the
// end: kCaptureEndOfStream, or the recording starts over (loop) with timestamps and sequences
// continuing. No allocation after start().

#include <memory>
#include <string>

#include "tlvlink/capture/frame_source.h"
#include "tlvlink/error.h"

namespace tlvlink::capture {

struct ReplayConfig {
  std::string label;           // for logs and errors; empty: the path
  std::string path;            // the recording
  bool realtime = true;        // pace frames by their recorded capture times
  bool loop = false;           // start over after the last frame
  bool verify = true;          // check each frame's CRC-32 (a mismatch is counted as a bad frame)
  uint32_t warmup_frames = 0;  // discarded once after start, as a camera's would be
};

// Checks the configuration only; start() opens and scans the recording.
Result<std::unique_ptr<FrameSource>> make_replay_source(const ReplayConfig& config);

}  // namespace tlvlink::capture
