#pragma once
// The bookkeeping every frame source shares: checks each buffer taken from the device, counts it
// in SourceStats (bad frames, warm-up, sequence gaps, stale frames), normalises sequence numbers
// and measures the frame rate from buffer timestamps. Pure logic, no I/O, no allocation.
//
// Per dequeued buffer the source calls admit(); of the buffers admitted in one drain it delivers
// the newest and reports the older ones with count_stale().

#include <cstdint>
#include <span>

#include "tlvlink/capture/frame_check.h"
#include "tlvlink/capture/frame_source.h"
#include "tlvlink/image/pixel_format.h"

namespace tlvlink::capture {

// One buffer as the driver returned it.
struct RawFrame {
  std::span<const uint8_t> bytes;  // bytesused
  uint32_t sequence = 0;           // the driver's 32-bit counter
  int64_t timestamp_ns = 0;
  bool error_flag = false;
};

enum class Admission : uint8_t {
  kDeliverable,  // a good frame: deliver it unless a newer one is ready
  kWarmup,       // good, but one of the warm-up frames discarded after open
  kBad,          // see problem(); counted and requeued
};

class FrameAccounting {
 public:
  static constexpr int kFpsWindow = 16;  // timestamps the frame rate is measured over

  // Borrows stats for its whole lifetime (the source owns both).
  explicit FrameAccounting(SourceStats& stats) : stats_(stats) {}

  // At every (re)open: sequences restart at 0, the next warmup_frames good frames are
  // discarded, the frame-rate window restarts.
  void reset_stream(uint32_t warmup_frames);

  // Checks and counts one buffer; sequence() and problem() describe it afterwards.
  Admission admit(const RawFrame& frame, const image::FrameFormat& format);

  uint64_t sequence() const { return sequence_; }  // normalised sequence of the last admit()
  FrameProblem problem() const { return problem_; }

  void count_stale(uint32_t frames) { stats_.skipped_stale += frames; }
  // For a source that skips stale frames without admitting them (a replay): the next admit()'s
  // sequence jumps over these `frames`, counted once, as stale, and not again as a gap.
  void skip_stale(uint32_t frames) {
    if (!first_) last_raw_ += frames;
    stats_.skipped_stale += frames;
  }
  void count_delivered() { ++stats_.delivered; }

 private:
  void count_sequence(uint32_t raw);
  void count_timestamp(int64_t timestamp_ns);

  SourceStats& stats_;
  bool first_ = true;
  uint32_t last_raw_ = 0;
  uint64_t sequence_ = 0;
  uint32_t warmup_left_ = 0;
  FrameProblem problem_ = FrameProblem::kNone;
  uint64_t frames_ = 0;  // buffers admitted since reset_stream()
  int64_t stamps_[kFpsWindow] = {};
  uint64_t stamp_frames_[kFpsWindow] = {};  // frames_ when each stamp was taken
  int stamp_count_ = 0;
  int stamp_next_ = 0;
};

}  // namespace tlvlink::capture
