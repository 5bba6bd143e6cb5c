// The V4L2 source's frame loop: newest-frame delivery, the dequeue watchdog and outages with
// bounded reconnection. Nothing here allocates while the device streams.
#include "tlvlink/capture/v4l2_source.h"

#include <linux/videodev2.h>
#include <poll.h>

#include <cstring>

#include "tlvlink/capture/outage.h"
#include "v4l2_internal.h"

namespace tlvlink::capture {

using internal::xioctl;

namespace {

int64_t timestamp_of(const v4l2_buffer& b, SourceStats& stats, int64_t dequeued_ns) {
  if ((b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC) {
    return static_cast<int64_t>(b.timestamp.tv_sec) * 1000000000 +
           static_cast<int64_t>(b.timestamp.tv_usec) * 1000;
  }
  stats.driver_timestamps = false;  // unknown or copied clock: the dequeue time is the best bound
  return dequeued_ns;
}

OutageBook outage_book(V4l2Source::State& s) { return {s.backoff, s.stats, s.last_reopen_error}; }

// Ends the stream and begins an outage; the returned error is what next() reports. The backoff
// restarts from backoff_initial_ms only if the device had delivered a frame since it was opened.
Error begin_outage(V4l2Source::State& s, const char* why, int err) {
  internal::close_device(s);
  capture::begin_outage(outage_book(s), s.streamed);
  return Error::make(ErrorCode::kCaptureDisconnected,
                     "%s: %s%s%s; reconnecting (first reopen in %d ms)", s.name, why,
                     err ? ": " : "", err ? std::strerror(err) : "", s.backoff.delay_ms());
}

// While disconnected (outage.h): reopen attempts until deadline_ns. Ok once streaming again.
Status reconnect(V4l2Source::State& s, int64_t deadline_ns) {
  auto reopen = [&s] { return internal::open_device(s); };
  return reconnect_until(outage_book(s), s.name, deadline_ns, reopen);
}

bool requeue(V4l2Source::State& s, uint32_t index, int& err) {
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  b.index = index;
  err = xioctl(s.fd, VIDIOC_QBUF, &b);
  return err == 0;
}

}  // namespace

V4l2Source::V4l2Source(std::unique_ptr<State> state) : state_(std::move(state)) {}
V4l2Source::~V4l2Source() { stop(); }

Status V4l2Source::start() {
  State& s = *state_;
  if (s.started) return Status();
  s.stats = SourceStats();
  s.backoff.reset();
  s.last_reopen_error = Error();
  Status st = internal::open_device(s);
  if (!st.ok()) {
    if (!s.config.wait_for_device || st.error().code() != ErrorCode::kCaptureNoDevice) return st;
    // Absent at start and allowed to be: an outage from the start, first attempt right away.
    s.backoff.absent_at_start(board_clock_ns());
    s.last_reopen_error = st.error();
  }
  s.started = true;
  return Status();
}

void V4l2Source::stop() {
  State& s = *state_;
  if (!s.started) return;
  end_outage_at_stop(outage_book(s));
  internal::close_device(s);
  s.started = false;
}

void V4l2Source::release() {
  State& s = *state_;
  if (s.held < 0 || s.fd < 0) return;
  int err = 0;
  if (!requeue(s, static_cast<uint32_t>(s.held), err)) s.pending_errno = err;
  s.held = -1;
}

Result<CapturedFrame> V4l2Source::next(int32_t timeout_ms) {
  State& s = *state_;
  if (!s.started) return Error::make(ErrorCode::kInvalidState, "%s: next() before start()", s.name);
  release();
  const int64_t deadline = board_clock_ns() + (timeout_ms > 0 ? timeout_ms : 0) * kNsPerMs;
  if (s.pending_errno != 0) return begin_outage(s, "VIDIOC_QBUF failed", s.pending_errno);
  if (!s.stats.connected) TLV_TRY(reconnect(s, deadline));

  for (;;) {
    // Drain everything ready; keep the newest good frame, give the others back at once.
    int newest = -1;
    uint32_t stale = 0;
    CapturedFrame frame;
    for (;;) {
      v4l2_buffer b{};
      b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      b.memory = V4L2_MEMORY_MMAP;
      const int err = xioctl(s.fd, VIDIOC_DQBUF, &b);
      if (err == EAGAIN) break;
      if (err != 0 || b.index >= s.buffer_count) {
        return begin_outage(s, "VIDIOC_DQBUF failed", err ? err : EINVAL);
      }
      const int64_t now = board_clock_ns();
      s.last_frame_ns = now;
      const internal::MappedBuffer& m = s.buffers[b.index];
      RawFrame raw{{m.data, b.bytesused <= m.length ? b.bytesused : m.length},
                   b.sequence,
                   timestamp_of(b, s.stats, now),
                   (b.flags & V4L2_BUF_FLAG_ERROR) != 0};
      int qerr = 0;
      if (s.accounting.admit(raw, s.format) == Admission::kDeliverable) {
        if (newest >= 0) {
          ++stale;
          if (!requeue(s, static_cast<uint32_t>(newest), qerr))
            return begin_outage(s, "VIDIOC_QBUF failed", qerr);
        }
        newest = static_cast<int>(b.index);
        frame.bytes = raw.bytes;
        frame.sequence = s.accounting.sequence();
        frame.timestamp_ns = raw.timestamp_ns;
      } else if (!requeue(s, b.index, qerr)) {
        return begin_outage(s, "VIDIOC_QBUF failed", qerr);
      }
    }
    if (newest >= 0) {
      s.accounting.count_stale(stale);
      s.accounting.count_delivered();
      s.streamed = true;
      s.held = newest;
      frame.format = s.format;
      frame.skipped_before = stale;
      return frame;
    }

    const int64_t now = board_clock_ns();
    const int64_t watchdog_at = s.last_frame_ns + static_cast<int64_t>(s.watchdog_ms) * kNsPerMs;
    if (now >= watchdog_at) {
      ++s.stats.stalls;
      return begin_outage(s, "no frame within the watchdog (device stalled)", 0);
    }
    if (now >= deadline) {
      ++s.stats.timeouts;
      return Error::make(ErrorCode::kCaptureTimeout, "%s: no frame within %d ms", s.name,
                         timeout_ms);
    }
    const int64_t until = deadline < watchdog_at ? deadline : watchdog_at;
    pollfd p{s.fd, POLLIN, 0};
    const int rc = ::poll(&p, 1, static_cast<int>((until - now + kNsPerMs - 1) / kNsPerMs));
    if (rc < 0 && errno != EINTR) return begin_outage(s, "poll failed", errno);
    if (rc > 0 && (p.revents & (POLLERR | POLLHUP | POLLNVAL)) && !(p.revents & POLLIN)) {
      // An unregistered node (unplugged) polls POLLERR|POLLHUP; so does a queue in error state
      // or one that stopped streaming. All our buffers are queued here, so none of it passes.
      return begin_outage(
          s, (p.revents & POLLHUP) ? "POLLHUP (device gone)" : "POLLERR (stream failed)", 0);
    }
  }
}

const image::FrameFormat& V4l2Source::format() const { return state_->format; }
const SourceStats& V4l2Source::stats() const { return state_->stats; }
const char* V4l2Source::name() const { return state_->name; }
const DeviceInfo& V4l2Source::device() const { return state_->device; }
const std::vector<AppliedControl>& V4l2Source::applied_controls() const { return state_->applied; }
uint32_t V4l2Source::buffer_count() const { return state_->buffer_count; }
size_t V4l2Source::buffer_bytes() const { return state_->buffers[0].length; }

}  // namespace tlvlink::capture
