#pragma once
// The libcamera frame source, for CSI-camera sensors (e.g. a Pi-camera GelSight) that V4L2 alone
// does not drive. Built with TLVLINK_WITH_LIBCAMERA (Debian's libcamera-dev 0.0.3); same
// FrameSource interface and the same frame checks and accounting as the V4L2 source.
//
//   LibcameraConfig c;
//   c.label = "pi-gel"; c.format = image::PixelFormat::kYuyv; c.width = 640; c.height = 480; c.fps
//   = 30; auto src = make_libcamera_source(c);   // validates; opens nothing Status s =
//   (*src)->start();             // kCaptureNoDevice: "libcamera ... found no camera"
//
// What start() does: the process-wide CameraManager (libcamera allows one per process) is started
// once; the camera named by camera_id (or the only one) is acquired, configured with one stream
// (role VideoRecording; validate() adjustments are refused like V4L2 size changes unless
// accept_other_size), `buffers` buffers are allocated, mapped read-only and queued, and the camera
// starts with FrameDurationLimits set from fps. Completed requests are handed from libcamera's
// thread to next() through a fixed ring and an eventfd; next() delivers the newest good frame and
// requeues the others (newest-frame policy), with FrameAccounting's checks and counters.
//
// Limits, said plainly: no libcamera-supported camera exists on the machines this was written on
// (Debian's kernels build no vimc; UVC cameras are left to the V4L2 source), so start() against a
// real camera, disconnect handling and reconnection were never run. What runs here: the build,
// camera enumeration, the "no camera" error, and the frame path on injected buffers
// (make_libcamera_source_for_test). libcamera allocates inside queueRequest(); this source does
// not promise allocation-free frames the way the V4L2 source does.

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/capture/frame_source.h"
#include "tlvlink/error.h"
#include "tlvlink/image/pixel_format.h"

namespace tlvlink::capture {

struct LibcameraConfig {
  std::string label;
  std::string camera_id;  // libcamera's id (list_libcamera_cameras); empty: the only camera
  image::PixelFormat format =
      image::PixelFormat::kYuyv;  // kRgb24 is libcamera's BGR888 (R,G,B bytes)
  int32_t width = 0, height = 0;
  double fps = 0;  // 0: the camera's default frame duration
  bool accept_other_size = false;
  uint32_t buffers = 4;        // kMinBuffers..kMaxBuffers (v4l2_source.h)
  uint32_t warmup_frames = 0;  // <= kMaxWarmupFrames
  int32_t backoff_initial_ms = 100, backoff_max_ms = 2000;  // reopen after a disconnect
};

Status validate_libcamera_config(const LibcameraConfig& config);

struct LibcameraCameraInfo {
  std::string id;     // what LibcameraConfig::camera_id takes
  std::string model;  // properties::Model, "" if unknown
};

// The cameras libcamera finds (starts the process-wide CameraManager). An empty list is not an
// error; a manager that cannot start is.
Result<std::vector<LibcameraCameraInfo>> list_libcamera_cameras();

// The libcamera version string ("v0.0.3").
std::string libcamera_version();

// A buffer as libcamera completed it: what the source takes from a finished request.
struct LibcameraCompletion {
  uint32_t buffer = 0;     // index of the source's buffer
  bool error = false;      // FrameMetadata::FrameError
  bool cancelled = false;  // FrameMetadata::FrameCancelled (the camera is stopping): ignored
  uint32_t sequence = 0;
  int64_t timestamp_ns = 0;  // FrameMetadata::timestamp (CLOCK_MONOTONIC)
  uint32_t bytesused = 0;    // of plane 0
};

class LibcameraSource final : public FrameSource {
 public:
  ~LibcameraSource() override;
  LibcameraSource(const LibcameraSource&) = delete;
  LibcameraSource& operator=(const LibcameraSource&) = delete;

  Status start() override;
  Result<CapturedFrame> next(int32_t timeout_ms) override;
  void release() override;
  void stop() override;
  const image::FrameFormat& format() const override;
  const SourceStats& stats() const override;
  const char* name() const override;

  // Test seam: hands a completed buffer to the source as libcamera's completion handler does
  // (any thread; never blocks). Only for sources from make_libcamera_source_for_test.
  void inject(const LibcameraCompletion& completion);
  // Buffers given back for refilling (the camera's queueRequest, or the test's counter).
  uint64_t requeued() const;

  struct State;  // private (src/libcamera)

 private:
  friend Result<std::unique_ptr<LibcameraSource>> make_libcamera_source(const LibcameraConfig&);
  friend Result<std::unique_ptr<LibcameraSource>> make_libcamera_source_for_test(
      const LibcameraConfig&, std::vector<std::span<const uint8_t>>);
  explicit LibcameraSource(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

Result<std::unique_ptr<LibcameraSource>> make_libcamera_source(const LibcameraConfig& config);

// A source bound to no camera: its buffers are the given memory (borrowed: it must outlive the
// source), start() only resets it, and frames arrive through inject(). The frame path from
// there on (checks, accounting, newest-frame, release) is the one a camera uses.
Result<std::unique_ptr<LibcameraSource>> make_libcamera_source_for_test(
    const LibcameraConfig& config, std::vector<std::span<const uint8_t>> buffers);

}  // namespace tlvlink::capture
