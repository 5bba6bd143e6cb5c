#include "tlvlink/capture/frame_accounting.h"

namespace tlvlink::capture {

void FrameAccounting::reset_stream(uint32_t warmup_frames) {
  first_ = true;
  sequence_ = 0;
  warmup_left_ = warmup_frames;
  stamp_count_ = 0;
  stamp_next_ = 0;
  frames_ = 0;
}

void FrameAccounting::count_sequence(uint32_t raw) {
  if (first_) {
    first_ = false;
    sequence_ = 0;
  } else {
    // Unsigned 32-bit difference: wraps of the driver's counter need no special case.
    const uint32_t delta = raw - last_raw_;
    if (delta == 0 || delta > 0x80000000u) {
      // Repeated or backwards: the driver restarted its counter. Renormalise from here.
      ++stats_.sequence_resets;
      ++sequence_;
    } else {
      stats_.dropped += delta - 1;
      sequence_ += delta;
    }
  }
  last_raw_ = raw;
}

void FrameAccounting::count_timestamp(int64_t timestamp_ns) {
  ++frames_;
  // A missing or non-increasing stamp (a flagged buffer may carry none) is left out of the
  // window; the frame still counts, so the rate stays the rate of frames.
  const int last = (stamp_next_ + kFpsWindow - 1) % kFpsWindow;
  if (timestamp_ns <= 0 || (stamp_count_ > 0 && timestamp_ns <= stamps_[last])) return;
  stamps_[stamp_next_] = timestamp_ns;
  stamp_frames_[stamp_next_] = frames_;
  stamp_next_ = (stamp_next_ + 1) % kFpsWindow;
  if (stamp_count_ < kFpsWindow) ++stamp_count_;
  if (stamp_count_ < 2) return;
  const int oldest = stamp_count_ < kFpsWindow ? 0 : stamp_next_;
  const int newest = (stamp_next_ + kFpsWindow - 1) % kFpsWindow;
  const int64_t span_ns = stamps_[newest] - stamps_[oldest];
  const uint64_t frames = stamp_frames_[newest] - stamp_frames_[oldest];
  stats_.measured_fps = static_cast<double>(frames) * 1e9 / static_cast<double>(span_ns);
}

Admission FrameAccounting::admit(const RawFrame& frame, const image::FrameFormat& format) {
  count_sequence(frame.sequence);
  count_timestamp(frame.timestamp_ns);
  problem_ = check_frame(frame.bytes, format, frame.error_flag);
  switch (problem_) {
    case FrameProblem::kNone: break;
    case FrameProblem::kErrorFlag: ++stats_.flagged_error; return Admission::kBad;
    case FrameProblem::kEmpty: ++stats_.empty; return Admission::kBad;
    case FrameProblem::kShort: ++stats_.short_frames; return Admission::kBad;
    case FrameProblem::kNoSoi:
    case FrameProblem::kNoEoi: ++stats_.bad_mjpeg; return Admission::kBad;
  }
  if (warmup_left_ > 0) {
    --warmup_left_;
    ++stats_.warmup_discarded;
    return Admission::kWarmup;
  }
  return Admission::kDeliverable;
}

}  // namespace tlvlink::capture
