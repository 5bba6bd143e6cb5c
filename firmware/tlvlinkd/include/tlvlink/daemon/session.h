#pragma once
// One running configuration of tlvlinkd: the model, an executor, every sensor's capture thread,
// the inference thread and the output thread. start() does all the allocation; from then on the
// frame path allocates nothing. stop() stops capture, lets the frames already decoded through,
// flushes every record already computed, and returns the run's totals.
//
// Tests create a session with their own frame sources (start_with_sources); the daemon's
// run_daemon() creates them from the configuration.

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "tlvlink/capture/frame_source.h"
#include "tlvlink/daemon/config.h"
#include "tlvlink/error.h"

namespace tlvlink::daemon {

struct SessionTotals {
  uint64_t frames = 0, encoded = 0, gated = 0, grasps = 0, grasps_not_computed = 0;
  uint64_t drops_stale = 0, drops_sequence = 0, drops_queue = 0, drops_output = 0;
  uint64_t bad_frames = 0, decode_errors = 0, inference_errors = 0, write_errors = 0;
  uint64_t failed_sources = 0;  // replays that stopped on an unusable recording
  double seconds = 0;
  double total_p50_ms = 0, total_p99_ms = 0;
  int64_t peak_rss_kb = 0;
  uint64_t images_sent = 0, images_busy = 0;  // FrameImages (frame_images on)
};

class Session {
 public:
  static Result<std::unique_ptr<Session>> start(const DaemonConfig& config);
  // `sources`: one per configured sensor, already started.
  static Result<std::unique_ptr<Session>> start_with_sources(
      const DaemonConfig& config, std::vector<std::unique_ptr<capture::FrameSource>> sources);
  ~Session();

  // True once max_frames were processed, or every source is a replay that ended (the caller
  // then stops the session).
  bool limit_reached() const;
  uint64_t frames_processed() const;
  // A controller command line ("rezero [N]", "closed", "lifting"); false when not a command.
  bool command(std::string_view line);
  SessionTotals stop();  // idempotent; prints the summary to stderr the first time

  struct Impl;

 private:
  explicit Session(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The daemon: sessions from the configuration at `path` until SIGTERM/SIGINT (or run_for_ms /
// max_frames), a new session on SIGHUP when the reloaded configuration is valid (an invalid one
// is reported and the running session continues). Returns the exit code: 0 after a clean stop
// (also when every output's reader left), 1 runtime error (model, camera, a replay that failed,
// records an output could not write), 2 configuration error.
int run_daemon(const std::string& path);

inline constexpr int kExitOk = 0, kExitRuntime = 1, kExitConfig = 2;

}  // namespace tlvlink::daemon
