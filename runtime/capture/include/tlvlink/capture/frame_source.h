#pragma once
// One interface for every camera backend: V4L2 (v4l2_source.h), libcamera (libcamera_source.h),
// and the simulated and replay sources. A source owns its device and its frame buffers; the
// caller borrows one frame at a time.
//
// Typical loop (one thread; a source is not thread-safe):
//   auto src = make_v4l2_source(config);             // Result<unique_ptr<V4l2Source>>
//   if (auto s = (*src)->start(); !s.ok()) exit_with(s.error());
//   for (;;) {
//     auto frame = (*src)->next(100);                // never blocks longer than 100 ms
//     if (!frame.ok()) { report(frame.error()); continue; }   // timeout, disconnected, ...
//     process(frame->bytes, frame->format, frame->timestamp_ns);
//     (*src)->release();                             // the buffer goes back to the device
//   }
//
// Ownership and lifetimes: CapturedFrame::bytes points into a buffer the source owns (an mmap'd
// V4L2 buffer). It stays valid and unchanged until release(), the next next(), stop() or the
// source's destruction, whichever comes first; copy what must live longer. next() releases a
// frame still held. stats() and format() are references into the source, valid while it lives.

#include <cstdint>
#include <span>

#include "tlvlink/error.h"
#include "tlvlink/image/pixel_format.h"

namespace tlvlink::capture {

// Limits every camera source shares (configurations outside them are refused, naming the field).
inline constexpr uint32_t kMinBuffers = 2;         // fewer cannot stream without gaps
inline constexpr uint32_t kMaxBuffers = 4;         // more only adds latency and memory
inline constexpr uint32_t kMaxWarmupFrames = 120;  // warm-up frames discarded after an open
inline constexpr int32_t kMinBackoffMs = 10,
                         kMaxBackoffMs = 60000;  // reopen delays after an outage

// A borrowed view of one frame (see the lifetime rules above).
struct CapturedFrame {
  std::span<const uint8_t> bytes;  // the payload the driver reported (bytesused)
  image::FrameFormat format;       // as negotiated (same as FrameSource::format())
  uint64_t sequence = 0;           // the driver's sequence, normalised so the first frame after
                                   // each (re)open is 0; a gap is a frame the device dropped
  int64_t timestamp_ns = 0;        // CLOCK_MONOTONIC capture time of the buffer (see
                                   // SourceStats::driver_timestamps for where it came from)
  uint32_t skipped_before = 0;     // older ready frames dropped (newest-frame policy) for this one
};

// Counters since start(). Every buffer a source takes from the device is counted exactly once in
// delivered, skipped_stale, warmup_discarded or one of the bad-frame counters; dropped counts the
// frames the device never handed over (sequence gaps).
struct SourceStats {
  uint64_t delivered = 0;         // frames returned by next()
  uint64_t skipped_stale = 0;     // ready but older than a newer ready frame (newest-frame policy)
  uint64_t dropped = 0;           // sequence gaps: frames lost before we could dequeue them
  uint64_t flagged_error = 0;     // the driver marked the buffer as an error (V4L2_BUF_FLAG_ERROR)
  uint64_t empty = 0;             // zero bytes of payload
  uint64_t short_frames = 0;      // fewer bytes than the negotiated uncompressed frame size
  uint64_t bad_mjpeg = 0;         // MJPEG without a start (SOI) or end (EOI) of image marker
  uint64_t warmup_discarded = 0;  // discarded after each open (e.g. a Mini's first black frames)
  uint64_t sequence_resets = 0;   // the driver's sequence went backwards (renormalised)
  uint64_t timeouts = 0;          // next() calls that ended without a frame while connected
  uint64_t stalls = 0;            // watchdog expiries: no frame for watchdog_ms, device reopened
  uint64_t disconnects = 0;       // outages begun (device gone, ENODEV/POLLHUP, stall)
  uint64_t reconnects = 0;        // outages ended by a successful reopen
  uint64_t reconnect_attempts = 0;  // reopen attempts that failed (the device was still absent)
  double measured_fps = 0;          // from the buffer timestamps of the last frames dequeued
  double nominal_fps = 0;           // the frame interval the device reported; 0 if unknown
  bool connected = false;           // streaming now
  bool driver_timestamps = true;    // false: the driver's timestamps are not CLOCK_MONOTONIC, so
                                    // the time of dequeue is used instead
  int64_t outage_ns = 0;  // time without a device since start(), the current outage included
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;

  // Opens the device, negotiates, maps buffers and starts streaming (allocates). An error names
  // the device and what failed; the source can be started again after an error.
  virtual Status start() = 0;

  // The newest frame ready, waiting at most timeout_ms (0: do not wait). Returns
  // kCaptureTimeout when none came, kCaptureDisconnected while the device is gone (reconnection
  // is attempted inside next() with bounded backoff; the call still returns within timeout_ms
  // plus one reopen attempt), kInvalidState before start(). Never aborts on device errors.
  virtual Result<CapturedFrame> next(int32_t timeout_ms) = 0;

  // Gives the buffer of the last frame back to the device. No-op when no frame is held.
  virtual void release() = 0;

  // Stops streaming and closes the device; start() may be called again. Idempotent.
  virtual void stop() = 0;

  virtual const image::FrameFormat& format() const = 0;  // valid after a successful start()
  virtual const SourceStats& stats() const = 0;
  // For logs and errors, e.g. "mini-left (0c45:636d SN 2BDF-Q7KX, /dev/video2)".
  virtual const char* name() const = 0;
};

}  // namespace tlvlink::capture
