// The libcamera source's frame path: completions -> checks and accounting -> newest frame; the
// outage after a camera disconnect and its bounded reopening.
#include "tlvlink/capture/libcamera_source.h"

#include <cstdio>

#include "libcamera/libcamera_internal.h"
#include "tlvlink/capture/outage.h"
#include "tlvlink/clock.h"

namespace tlvlink::capture {
namespace {

const char* label_of(const LibcameraConfig& c) {
  return c.label.empty() ? "libcamera" : c.label.c_str();
}

Status open_session(LibcameraSource::State& s) {
  s.completions.clear();
  auto session = internal::open_camera(s.config, label_of(s.config), s.completions);
  if (!session.ok()) return session.error();
  s.session = std::move(*session);
  s.format = s.session->format;
  s.stats.nominal_fps = s.session->nominal_fps;
  std::snprintf(s.name, sizeof(s.name), "%s (libcamera %s)", label_of(s.config), s.session->camera);
  s.accounting.reset_stream(s.config.warmup_frames);
  s.held = -1;
  s.streamed = false;
  s.stats.connected = true;
  return Status();
}

OutageBook outage_book(LibcameraSource::State& s) {
  return {s.backoff, s.stats, s.last_reopen_error};
}

Error begin_outage(LibcameraSource::State& s) {
  s.session.reset();
  s.stats.connected = false;
  capture::begin_outage(outage_book(s), s.streamed);  // outage.h, as the V4L2 source
  return Error::make(ErrorCode::kCaptureDisconnected,
                     "%s: camera disconnected; reconnecting (first reopen in %d ms)", s.name,
                     s.backoff.delay_ms());
}

// Bounded reopening while the camera is gone (outage.h: the V4L2 source's loop).
Status reconnect(LibcameraSource::State& s, int64_t deadline) {
  auto reopen = [&s] { return open_session(s); };
  return reconnect_until(outage_book(s), s.name, deadline, reopen);
}

}  // namespace

Status validate_libcamera_config(const LibcameraConfig& c) {
  const char* label = label_of(c);
  TLV_ENSURE(c.width > 0 && c.height > 0 && c.width <= 16384 && c.height <= 16384,
             ErrorCode::kInvalidArgument, "%s: size %dx%d: width and height must be 1..16384",
             label, c.width, c.height);
  TLV_ENSURE(image::pixel_format_fourcc(c.format) != 0, ErrorCode::kInvalidArgument,
             "%s: unknown pixel format", label);
  TLV_ENSURE(c.fps >= 0 && c.fps <= 1000, ErrorCode::kInvalidArgument,
             "%s: fps %.3f: must be 0..1000", label, c.fps);
  TLV_ENSURE(c.buffers >= kMinBuffers && c.buffers <= kMaxBuffers, ErrorCode::kInvalidArgument,
             "%s: buffers %u: must be %u..%u", label, c.buffers, kMinBuffers, kMaxBuffers);
  TLV_ENSURE(c.warmup_frames <= kMaxWarmupFrames, ErrorCode::kInvalidArgument,
             "%s: warmup_frames %u: at most %u", label, c.warmup_frames, kMaxWarmupFrames);
  TLV_ENSURE(c.backoff_initial_ms >= kMinBackoffMs && c.backoff_max_ms <= kMaxBackoffMs &&
                 c.backoff_initial_ms <= c.backoff_max_ms,
             ErrorCode::kInvalidArgument, "%s: backoff %d..%d ms out of range", label,
             c.backoff_initial_ms, c.backoff_max_ms);
  return Status();
}

Result<std::unique_ptr<LibcameraSource>> make_libcamera_source(const LibcameraConfig& config) {
  TLV_TRY(validate_libcamera_config(config));
  auto state = std::make_unique<LibcameraSource::State>(config);
  TLV_ENSURE(state->completions.ok(), ErrorCode::kCapture, "%s: eventfd failed", label_of(config));
  state->format = {config.format, config.width, config.height, 0};
  std::snprintf(state->name, sizeof(state->name), "%s (libcamera %s)", label_of(config),
                config.camera_id.empty() ? "any camera" : config.camera_id.c_str());
  return std::unique_ptr<LibcameraSource>(new LibcameraSource(std::move(state)));
}

Result<std::unique_ptr<LibcameraSource>> make_libcamera_source_for_test(
    const LibcameraConfig& config, std::vector<std::span<const uint8_t>> buffers) {
  TLV_ASSIGN_OR_RETURN(auto src, make_libcamera_source(config));
  TLV_ENSURE(buffers.size() >= 1 && buffers.size() <= internal::kMaxCompletions,
             ErrorCode::kInvalidArgument, "%zu test buffers: need 1..%u", buffers.size(),
             internal::kMaxCompletions);
  src->state_->test_mode = true;
  src->state_->test_buffers = std::move(buffers);
  std::snprintf(src->state_->name, sizeof(src->state_->name), "%s (libcamera test buffers)",
                label_of(config));
  return src;
}

LibcameraSource::LibcameraSource(std::unique_ptr<State> state) : state_(std::move(state)) {}
LibcameraSource::~LibcameraSource() { stop(); }

Status LibcameraSource::start() {
  State& s = *state_;
  if (s.started) return Status();
  s.stats = SourceStats();
  s.backoff.reset();
  if (s.test_mode) {
    s.accounting.reset_stream(s.config.warmup_frames);
    s.stats.connected = true;
  } else {
    TLV_TRY(open_session(s));
  }
  s.started = true;
  return Status();
}

void LibcameraSource::stop() {
  State& s = *state_;
  if (!s.started) return;
  end_outage_at_stop(outage_book(s));
  s.session.reset();
  s.completions.clear();
  s.held = -1;
  s.stats.connected = false;
  s.started = false;
}

void LibcameraSource::release() {
  State& s = *state_;
  if (s.held < 0) return;
  s.requeue(static_cast<uint32_t>(s.held));
  s.held = -1;
}

void LibcameraSource::inject(const LibcameraCompletion& c) { state_->completions.push(c); }
uint64_t LibcameraSource::requeued() const { return state_->requeued.load(); }

Result<CapturedFrame> LibcameraSource::next(int32_t timeout_ms) {
  State& s = *state_;
  if (!s.started) return Error::make(ErrorCode::kInvalidState, "%s: next() before start()", s.name);
  release();
  const int64_t deadline = board_clock_ns() + (timeout_ms > 0 ? timeout_ms : 0) * kNsPerMs;
  if (!s.test_mode) {
    if (s.session && s.session->disconnected()) return begin_outage(s);
    if (!s.session) TLV_TRY(reconnect(s, deadline));
  }
  for (;;) {
    int newest = -1;
    uint32_t stale = 0;
    CapturedFrame frame;
    LibcameraCompletion c;
    while (s.completions.pop(c)) {
      if (c.cancelled) continue;  // the camera is stopping; nothing was captured
      const std::span<const uint8_t> mem = s.buffer(c.buffer);
      if (mem.empty()) continue;  // not one of ours
      const RawFrame raw{mem.first(c.bytesused <= mem.size() ? c.bytesused : mem.size()),
                         c.sequence, c.timestamp_ns, c.error};
      if (s.accounting.admit(raw, s.format) == Admission::kDeliverable) {
        if (newest >= 0) {
          ++stale;
          s.requeue(static_cast<uint32_t>(newest));
        }
        newest = static_cast<int>(c.buffer);
        frame.bytes = raw.bytes;
        frame.sequence = s.accounting.sequence();
        frame.timestamp_ns = raw.timestamp_ns;
      } else {
        s.requeue(c.buffer);
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
    if (s.session && s.session->disconnected()) return begin_outage(s);
    const int64_t now = board_clock_ns();
    if (now >= deadline) {
      ++s.stats.timeouts;
      return Error::make(ErrorCode::kCaptureTimeout, "%s: no frame within %d ms", s.name,
                         timeout_ms);
    }
    s.completions.wait(static_cast<int>((deadline - now + kNsPerMs - 1) / kNsPerMs));
  }
}

const image::FrameFormat& LibcameraSource::format() const { return state_->format; }
const SourceStats& LibcameraSource::stats() const { return state_->stats; }
const char* LibcameraSource::name() const { return state_->name; }

}  // namespace tlvlink::capture
