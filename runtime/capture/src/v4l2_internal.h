#pragma once
// Internals of the V4L2 source: its state and the steps of opening a device. Private to
// runtime/capture (the CMake target defines TLVLINK_CAPTURE_PRIVATE).
#ifndef TLVLINK_CAPTURE_PRIVATE
#error "runtime/capture internal header: include tlvlink/capture/v4l2_source.h instead"
#endif

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tlvlink/capture/frame_accounting.h"
#include "tlvlink/capture/reconnect_backoff.h"
#include "tlvlink/capture/v4l2_source.h"
#include "tlvlink/clock.h"

namespace tlvlink::capture::internal {

// The driver may grant more buffers than asked (its minimum); more than this is refused.
inline constexpr uint32_t kMaxGrantedBuffers = 8;

struct MappedBuffer {
  const uint8_t* data = nullptr;  // PROT_READ mapping: a frame cannot be written by mistake
  size_t length = 0;
};

// ioctl() retried on EINTR; 0 or the errno.
int xioctl(int fd, unsigned long request, void* arg);

}  // namespace tlvlink::capture::internal

namespace tlvlink::capture {

struct V4l2Source::State {
  explicit State(const V4l2Config& c)
      : config(c), backoff(c.backoff_initial_ms, c.backoff_max_ms) {}

  V4l2Config config;
  char name[192] = {};
  DeviceInfo device;
  SourceStats stats;
  FrameAccounting accounting{stats};
  image::FrameFormat format;  // fixed by the first successful open
  bool format_fixed = false;
  std::vector<AppliedControl> applied;
  int32_t watchdog_ms = 1000;  // effective (config raised to 4 frame periods)

  // The open device.
  int fd = -1;
  internal::MappedBuffer buffers[internal::kMaxGrantedBuffers];
  uint32_t buffer_count = 0;
  int held = -1;              // buffer index delivered and not yet released
  int pending_errno = 0;      // a release() that found the device gone: next() ends the stream;
                              // belongs to the open device (cleared when it is closed)
  bool streamed = false;      // a frame was delivered since the device was opened
  int64_t last_frame_ns = 0;  // watchdog reference: last dequeue (or stream start + grace)

  // Lifecycle and outages.
  bool started = false;
  ReconnectBackoff backoff;
  Error last_reopen_error;
};

namespace internal {

// Finds the device, opens it, applies controls, negotiates, maps buffers, starts streaming.
// On failure everything opened is closed again and the error names the device and the step.
Status open_device(V4l2Source::State& s);
// STREAMOFF, unmap, free the buffers, close. Safe on a device that is gone.
void close_device(V4l2Source::State& s);

// S_FMT/G_FMT then S_PARM/G_PARM on an open fd; fills s.format (first open) or checks it (later
// opens) and s.stats.nominal_fps.
Status negotiate(V4l2Source::State& s);
// REQBUFS + QUERYBUF + mmap + QBUF of every buffer.
Status map_buffers(V4l2Source::State& s);
void unmap_buffers(V4l2Source::State& s);
// Every configured control, in order, read back into s.applied.
Status apply_controls(V4l2Source::State& s);

}  // namespace internal
}  // namespace tlvlink::capture
