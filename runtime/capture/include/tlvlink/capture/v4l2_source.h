#pragma once
// The V4L2 frame source: a UVC camera (GelSight Mini, DIGIT) or any single-planar V4L2 capture
// node, with mmap streaming, newest-frame delivery and reconnection.
//
//   V4l2Config c;
//   c.label = "mini-left";
//   c.device = parse_device_selector("usb:0c45:636d:2BDF-Q7KX").value();
//   c.format = image::PixelFormat::kMjpeg; c.width = 3280; c.height = 2464; c.fps = 25;
//   c.warmup_frames = 5;
//   c.controls = parse_controls("auto_exposure=1, exposure_time_absolute=180").value();
//   auto src = make_v4l2_source(c);   // validates the configuration; opens nothing yet
//
// What start() does: find the node (device_select.h), open it O_RDWR|O_NONBLOCK|O_CLOEXEC, check
// it captures video, apply the controls, S_FMT then G_FMT (what the driver set is what counts),
// S_PARM after S_FMT (drivers may reset the interval on S_FMT) then G_PARM, request and mmap
// `buffers` buffers, queue them, STREAMON.
//
// What next() does: poll() with the caller's timeout; dequeue every ready buffer; check each
// (frame_check.h) and count it (frame_accounting.h); deliver the newest good one and requeue the
// rest (newest-frame policy: a slow consumer gets the latest frame, never a backlog). Timestamps
// are the driver's when it reports CLOCK_MONOTONIC ones (V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC,
// as uvcvideo and vivid do); otherwise the dequeue time on CLOCK_MONOTONIC, and
// SourceStats::driver_timestamps is false. No heap allocation in next() or release() while the
// device streams.
//
// Outages: ENODEV/EIO from the device, POLLHUP/POLLERR, or no frame for watchdog_ms (a stalled
// camera) close the device and start an outage: next() returns kCaptureDisconnected, and each
// later next() reopens the device (same identity: same VID:PID and serial, or the same path)
// when the backoff allows, doubling the wait from backoff_initial_ms up to backoff_max_ms. A
// reopen applies the controls again and discards warm-up frames again; it must negotiate the same
// format as the first open or it counts as a failed attempt. Outages are counted in SourceStats.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tlvlink/capture/controls.h"
#include "tlvlink/capture/device_select.h"
#include "tlvlink/capture/frame_source.h"
#include "tlvlink/error.h"
#include "tlvlink/image/pixel_format.h"

namespace tlvlink::capture {

struct V4l2Config {
  std::string label;      // "mini-left": names the source in errors
  DeviceSelector device;  // identity (or a path for test devices)
  DeviceRoots roots;      // where to look (tests: a fake sysfs)
  image::PixelFormat format = image::PixelFormat::kMjpeg;
  int32_t width = 0, height = 0;   // > 0
  double fps = 0;                  // 0: keep the device's frame interval
  bool accept_other_size = false;  // a device that sets another size: error (false) or use it
                                   // (true; format() and every frame report the real size)
  uint32_t buffers = 4;            // mmap buffers, kMinBuffers..kMaxBuffers: 2 is the least that
                                   // streams without gaps; 4 is what libcamera's UVC pipeline uses
  uint32_t warmup_frames = 0;      // good frames discarded after each open, <= kMaxWarmupFrames
  int32_t watchdog_ms = 1000;      // no frame this long while streaming = stalled device; raised to
                                   // 4 frame periods when the interval is slower (OpenCV: 10 s)
  int32_t backoff_initial_ms = 100;  // first reopen delay after an outage begins
  int32_t backoff_max_ms = 2000;     // the delay doubles up to this bound
  bool wait_for_device = false;      // start() succeeds while the device is absent (an outage from
                                     // the start); default: start() fails with kCaptureNoDevice
  std::vector<ControlSetting> controls;  // applied at every open, in order
};

inline constexpr int32_t kMinWatchdogMs = 50, kMaxWatchdogMs = 60000;

// Checks ranges and consistency; errors name the field (kInvalidArgument).
Status validate_v4l2_config(const V4l2Config& config);

// A control as applied on the device (after name resolution), for reports.
struct AppliedControl {
  std::string key;    // as configured
  uint32_t id = 0;    // resolved V4L2 id
  int64_t value = 0;  // the value read back after setting it
};

class V4l2Source final : public FrameSource {
 public:
  ~V4l2Source() override;
  V4l2Source(const V4l2Source&) = delete;
  V4l2Source& operator=(const V4l2Source&) = delete;

  Status start() override;
  Result<CapturedFrame> next(int32_t timeout_ms) override;
  void release() override;
  void stop() override;
  const image::FrameFormat& format() const override;
  const SourceStats& stats() const override;
  const char* name() const override;

  // The node in use (or last used); empty before the first successful open.
  const DeviceInfo& device() const;
  // The controls as read back after the last open.
  const std::vector<AppliedControl>& applied_controls() const;
  // Buffers the driver granted (it may round the request up) and bytes per buffer.
  uint32_t buffer_count() const;
  size_t buffer_bytes() const;

  struct State;  // private (src/)

 private:
  friend Result<std::unique_ptr<V4l2Source>> make_v4l2_source(const V4l2Config&);
  explicit V4l2Source(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

Result<std::unique_ptr<V4l2Source>> make_v4l2_source(const V4l2Config& config);

}  // namespace tlvlink::capture
