#include "capture_worker.h"

#include <time.h>

#include <cstdarg>
#include <cstdio>

#include "clock.h"
#include "tlvlink/log.h"

namespace tlvlink::daemon::internal {
namespace {

TLV_LOG_CATEGORY(kLogCapture, "capture");
constexpr int32_t kPollMs = 100;  // how often stop is checked
constexpr int64_t kPollNs = int64_t{kPollMs} * 1'000'000;
constexpr int64_t kDecodeEventIntervalNs =
    1'000'000'000;  // at most one decode error event a second

}  // namespace

CaptureWorker::CaptureWorker(int32_t index, std::string name,
                             std::unique_ptr<capture::FrameSource> source,
                             image::FrameDecoder decoder, FrameRing& ring, OutputQueue& events,
                             const std::atomic<bool>& stop)
    : index_(index),
      name_(std::move(name)),
      source_(std::move(source)),
      decoder_(std::move(decoder)),
      ring_(ring),
      events_(events),
      stop_(stop) {}

void CaptureWorker::event(bool error, const char* format, ...) {
  EventRecord e;
  e.t_ns = board_clock_ns();
  e.sensor = index_;
  e.error = error;
  va_list args;
  va_start(args, format);
  std::vsnprintf(e.text.data(), e.text.size(), format, args);
  va_end(args);
  TLV_LOG(kLogCapture, kWarning, "%s: %s", name_.c_str(), e.text.data());
  events_.push(e);
}

void CaptureWorker::handle_error(const Error& e) {
  switch (e.code()) {
    case ErrorCode::kCaptureTimeout: return;  // counted by the source
    case ErrorCode::kCaptureDisconnected:
      if (!in_outage_) event(true, "camera lost: %s", e.message());
      in_outage_ = true;
      return;
    default: event(true, "%s", e.message());
  }
}

void CaptureWorker::run() {
  cpu_clock_ = this_thread_cpu_clock();
  while (!stop_.load(std::memory_order_relaxed)) {
    const int64_t asked_ns = board_clock_ns();
    auto frame = source_->next(kPollMs);
    if (!frame.ok() && frame.error().code() == ErrorCode::kCaptureEndOfStream) {
      event(false, "%s", frame.error().message());  // a replay without loop: nothing more comes
      ended_.store(true);
      break;
    }
    if (!frame.ok() && frame.error().code() == ErrorCode::kFormat) {
      event(true, "%s", frame.error().message());  // the recording is unusable: no retry helps
      failed_.store(true);
      ended_.store(true);
      break;
    }
    if (!frame.ok()) {
      handle_error(frame.error());
      // Sources wait their timeout while a camera is gone; one that fails at once must not turn
      // this loop into a spin either: an error costs at least one poll period.
      const int64_t until = asked_ns + kPollNs;
      if (board_clock_ns() < until) sleep_until_ns(until);
    } else {
      if (in_outage_) {
        const capture::SourceStats& st = source_->stats();
        event(false,
              "camera back (outage %llu; %.2f s without camera in all, %llu reopen "
              "attempts failed)",
              static_cast<unsigned long long>(st.disconnects),
              static_cast<double>(st.outage_ns) * 1e-9,
              static_cast<unsigned long long>(st.reconnect_attempts));
        in_outage_ = false;
      }
      DecodedFrame* slot = ring_.acquire(stop_);
      if (slot == nullptr) {  // stopped while waiting for the consumer (a replay read at speed)
        source_->release();
        break;
      }
      slot->sequence = frame->sequence;
      slot->times = {};
      slot->times.capture_ns = frame->timestamp_ns;
      slot->times.dequeued_ns = board_clock_ns();
      const Status decoded = decoder_.decode(frame->bytes, slot->rgb, name_.c_str());
      source_->release();  // the camera gets its buffer back before anything else
      if (decoded.ok()) {
        slot->times.decoded_ns = board_clock_ns();
        ring_.publish(slot);
      } else {
        ring_.discard(slot);
        const int64_t now = board_clock_ns();
        std::lock_guard lock(mutex_);
        ++snapshot_.decode_errors;
        if (now - last_decode_event_ns_ >= kDecodeEventIntervalNs) {
          last_decode_event_ns_ = now;
          event(true, "frame %llu not decoded (%llu so far): %s",
                static_cast<unsigned long long>(frame->sequence),
                static_cast<unsigned long long>(snapshot_.decode_errors),
                decoded.error().message());
        }
      }
    }
    std::lock_guard lock(mutex_);
    snapshot_.source = source_->stats();
  }
  source_->stop();
  final_cpu_ns_ = thread_cpu_ns(cpu_clock_.load());
  std::lock_guard lock(mutex_);
  snapshot_.source = source_->stats();
}

CaptureSnapshot CaptureWorker::snapshot() const {
  std::lock_guard lock(mutex_);
  CaptureSnapshot s = snapshot_;
  const clockid_t clock = cpu_clock_.load();
  const int64_t final_cpu = final_cpu_ns_.load();
  s.cpu_ns = final_cpu >= 0 ? final_cpu : clock == -1 ? 0 : thread_cpu_ns(clock);
  return s;
}

}  // namespace tlvlink::daemon::internal
