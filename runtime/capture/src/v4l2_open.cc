// Configuration checks, and opening / closing the device (every step of start()).
#include <fcntl.h>
#include <linux/videodev2.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>

#include "v4l2_internal.h"

namespace tlvlink::capture {
namespace internal {
namespace {

void set_name(V4l2Source::State& s) {
  const char* label = s.config.label.empty() ? "v4l2" : s.config.label.c_str();
  const DeviceInfo& d = s.device;
  if (d.path.empty()) {
    std::snprintf(s.name, sizeof(s.name), "%s (%s)", label,
                  describe_selector(s.config.device).c_str());
  } else if (d.vendor_id != 0 || d.product_id != 0) {
    std::snprintf(s.name, sizeof(s.name), "%s (%04x:%04x SN %s, %s)", label, d.vendor_id,
                  d.product_id, d.serial.empty() ? "-" : d.serial.c_str(), d.path.c_str());
  } else {
    std::snprintf(s.name, sizeof(s.name), "%s (%s '%s')", label, d.path.c_str(), d.name.c_str());
  }
}

Status open_steps(V4l2Source::State& s) {
  TLV_ASSIGN_OR_RETURN(DeviceInfo found, find_v4l2_device(s.config.device, s.config.roots));
  s.device = std::move(found);
  set_name(s);
  s.fd = ::open(s.device.path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (s.fd < 0) {
    const int err = errno;
    return Error::make(
        err == ENOENT || err == ENODEV ? ErrorCode::kCaptureNoDevice : ErrorCode::kCapture,
        "%s: open: %s%s", s.name, std::strerror(err),
        err == EACCES ? " (add the user to group 'video' or install the udev rule)" : "");
  }
  TLV_TRY(apply_controls(s));
  TLV_TRY(negotiate(s));
  TLV_TRY(map_buffers(s));
  v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (int err = xioctl(s.fd, VIDIOC_STREAMON, &type); err != 0) {
    return Error::make(ErrorCode::kCapture, "%s: VIDIOC_STREAMON: %s", s.name, std::strerror(err));
  }
  return Status();
}

}  // namespace

Status open_device(V4l2Source::State& s) {
  Status st = open_steps(s);
  if (!st.ok()) {
    close_device(s);
    return st;
  }
  // A slow interval needs a longer watchdog: at least 4 frame periods.
  s.watchdog_ms = s.config.watchdog_ms;
  if (s.stats.nominal_fps > 0) {
    const auto four_periods = static_cast<int32_t>(4000.0 / s.stats.nominal_fps) + 1;
    if (four_periods > s.watchdog_ms) s.watchdog_ms = four_periods;
  }
  s.accounting.reset_stream(s.config.warmup_frames);
  // The first frame may take longer than the next ones (sensor start-up): one watchdog of grace.
  s.last_frame_ns = board_clock_ns() + static_cast<int64_t>(s.watchdog_ms) * 1000000;
  s.held = -1;
  s.pending_errno = 0;
  s.streamed = false;
  s.stats.connected = true;
  return Status();
}

void close_device(V4l2Source::State& s) {
  if (s.fd >= 0) {
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    xioctl(s.fd, VIDIOC_STREAMOFF, &type);
  }
  unmap_buffers(s);
  if (s.fd >= 0) ::close(s.fd);
  s.fd = -1;
  // A failed requeue of the device just closed is not an error of the next one: left set, it
  // would end every later next() at once (no reopen, no wait: a spinning caller).
  s.pending_errno = 0;
  s.stats.connected = false;
}

}  // namespace internal

Status validate_v4l2_config(const V4l2Config& c) {
  const char* label = c.label.empty() ? "v4l2" : c.label.c_str();
  TLV_ENSURE(!c.device.path.empty() || c.device.vendor_id != 0 || c.device.product_id != 0,
             ErrorCode::kInvalidArgument, "%s: device: no USB id or path given", label);
  TLV_ENSURE(image::pixel_format_fourcc(c.format) != 0, ErrorCode::kInvalidArgument,
             "%s: format: unknown pixel format", label);
  TLV_ENSURE(c.width > 0 && c.height > 0 && c.width <= 16384 && c.height <= 16384,
             ErrorCode::kInvalidArgument, "%s: size %dx%d: width and height must be 1..16384",
             label, c.width, c.height);
  TLV_ENSURE(c.fps >= 0 && c.fps <= 1000, ErrorCode::kInvalidArgument,
             "%s: fps %.3f: must be 0 (keep the device's) or up to 1000", label, c.fps);
  TLV_ENSURE(c.buffers >= kMinBuffers && c.buffers <= kMaxBuffers, ErrorCode::kInvalidArgument,
             "%s: buffers %u: must be %u..%u", label, c.buffers, kMinBuffers, kMaxBuffers);
  TLV_ENSURE(c.warmup_frames <= kMaxWarmupFrames, ErrorCode::kInvalidArgument,
             "%s: warmup_frames %u: at most %u", label, c.warmup_frames, kMaxWarmupFrames);
  TLV_ENSURE(c.watchdog_ms >= kMinWatchdogMs && c.watchdog_ms <= kMaxWatchdogMs,
             ErrorCode::kInvalidArgument, "%s: watchdog_ms %d: must be %d..%d", label,
             c.watchdog_ms, kMinWatchdogMs, kMaxWatchdogMs);
  TLV_ENSURE(c.backoff_initial_ms >= kMinBackoffMs && c.backoff_max_ms <= kMaxBackoffMs &&
                 c.backoff_initial_ms <= c.backoff_max_ms,
             ErrorCode::kInvalidArgument,
             "%s: backoff %d..%d ms: need %d <= backoff_initial_ms <= backoff_max_ms <= %d", label,
             c.backoff_initial_ms, c.backoff_max_ms, kMinBackoffMs, kMaxBackoffMs);
  TLV_ENSURE(c.controls.size() <= kMaxControls, ErrorCode::kInvalidArgument,
             "%s: %zu controls: at most %zu", label, c.controls.size(), kMaxControls);
  return Status();
}

Result<std::unique_ptr<V4l2Source>> make_v4l2_source(const V4l2Config& config) {
  TLV_TRY(validate_v4l2_config(config));
  auto state = std::make_unique<V4l2Source::State>(config);
  state->format = {config.format, config.width, config.height, 0};
  state->watchdog_ms = config.watchdog_ms;
  std::snprintf(state->name, sizeof(state->name), "%s (%s)",
                config.label.empty() ? "v4l2" : config.label.c_str(),
                describe_selector(config.device).c_str());
  return std::unique_ptr<V4l2Source>(new V4l2Source(std::move(state)));
}

}  // namespace tlvlink::capture
