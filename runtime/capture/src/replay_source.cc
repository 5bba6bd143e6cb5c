#include "tlvlink/capture/replay_source.h"

#include <algorithm>
#include <optional>
#include <vector>

#include "tlvlink/capture/frame_accounting.h"
#include "tlvlink/capture/recording.h"
#include "tlvlink/clock.h"
#include "tlvlink/log.h"

namespace tlvlink::capture {
namespace {

TLV_LOG_CATEGORY(kLogReplay, "replay");

class ReplaySource final : public FrameSource {
 public:
  explicit ReplaySource(ReplayConfig c) : config_(std::move(c)), accounting_(stats_) {
    if (config_.label.empty()) config_.label = config_.path;
  }

  Status start() override {
    stop();
    auto reader = RecordingReader::open(config_.path);
    if (!reader.ok()) return reader.error().with_context("replay '%s'", config_.label.c_str());
    reader_.emplace(std::move(reader).value());
    const RecordingSummary& s = reader_->summary();
    TLV_ENSURE(s.frames > 0, ErrorCode::kFormat, "replay '%s': recording %s holds no frame",
               config_.label.c_str(), config_.path.c_str());
    format_ = s.format.format;
    buffer_.assign(s.max_frame_bytes, 0);
    stats_ = SourceStats{};
    stats_.nominal_fps = s.format.nominal_fps();
    stats_.connected = true;
    accounting_.reset_stream(config_.warmup_frames);
    // One loop lasts the recording's span plus one frame period, so the first frame of the next
    // pass keeps the pace.
    const double fps = stats_.nominal_fps > 0 ? stats_.nominal_fps : 25.0;
    loop_span_ns_ = s.last_offset_ns - s.first_offset_ns + static_cast<int64_t>(1e9 / fps);
    loop_sequences_ = s.last_sequence - s.first_sequence + 1;
    first_sequence_ = s.first_sequence;
    passes_ = 0;
    bad_run_ = 0;
    // Bytes after the last complete record: a writer that died mid-record, or a record whose
    // length is forged. Either way a frame is lost: said once here and counted as a short frame.
    if (s.truncated_records > 0) {
      stats_.short_frames += s.truncated_records;
      TLV_LOG(kLogReplay, kWarning,
              "replay '%s': %s ends in %llu bytes that are not a complete record (cut short or a "
              "forged length) after %llu frames: ignored",
              config_.label.c_str(), config_.path.c_str(),
              static_cast<unsigned long long>(s.truncated_bytes),
              static_cast<unsigned long long>(s.frames));
    }
    next_record_ = reader_->first_record();
    start_ns_ = board_clock_ns();
    return {};
  }

  Result<CapturedFrame> next(int32_t timeout_ms) override {
    TLV_ENSURE(reader_.has_value(), ErrorCode::kInvalidState, "replay '%s': not started",
               config_.label.c_str());
    const int64_t deadline =
        board_clock_ns() + static_cast<int64_t>(std::max(timeout_ms, 0)) * kNsPerMs;
    for (;;) {
      RecordInfo info;
      TLV_ASSIGN_OR_RETURN(bool have, peek(info));
      if (!have) {
        const RecordingSummary& s = reader_->summary();
        return Error::make(ErrorCode::kCaptureEndOfStream, "replay '%s': end of %s (%llu frames%s)",
                           config_.label.c_str(), config_.path.c_str(),
                           static_cast<unsigned long long>(s.frames),
                           s.truncated_records > 0 ? "; its incomplete last record ignored" : "");
      }
      // Looping over a recording none of whose frames is good would never return.
      TLV_ENSURE(bad_run_ < reader_->summary().frames, ErrorCode::kFormat,
                 "replay '%s': no good frame in a whole pass of %s (%llu frames: every one "
                 "failed its checksum or was flagged)",
                 config_.label.c_str(), config_.path.c_str(),
                 static_cast<unsigned long long>(reader_->summary().frames));
      uint32_t stale = 0;
      if (config_.realtime) {
        const int64_t due = due_ns(info);
        if (due > board_clock_ns()) {
          if (due > deadline) {
            sleep_until_ns(deadline);
            ++stats_.timeouts;
            return Error::make(ErrorCode::kCaptureTimeout, "replay '%s': no frame within %d ms",
                               config_.label.c_str(), timeout_ms);
          }
          sleep_until_ns(due);
        }
        // Newest-frame policy: frames that became due while the consumer was busy are skipped.
        for (;;) {
          RecordInfo newer;
          const uint64_t saved = next_record_;
          const uint32_t saved_passes = passes_;
          next_record_ = info.next;
          TLV_ASSIGN_OR_RETURN(const bool more, peek(newer));
          if (!more || due_ns(newer) > board_clock_ns()) {
            next_record_ = saved;
            passes_ = saved_passes;
            break;
          }
          info = newer;
          ++stale;
        }
      }
      // The recorded timeline, also when read at speed: what runs on frame times (smoothing, the
      // grasp tracker, frame images) sees the camera's pace whatever the replay's speed.
      const int64_t stamp = due_ns(info);
      next_record_ = info.next;
      Status read = reader_->read_frame(info, buffer_, config_.verify);
      RawFrame raw;
      raw.bytes = std::span<const uint8_t>(buffer_.data(), read.ok() ? info.bytes : 0);
      raw.sequence = info.sequence + passes_ * loop_sequences_;
      raw.timestamp_ns = stamp;
      raw.error_flag = (info.flags & kRecordErrorFlag) != 0 || !read.ok();
      if (!read.ok() && read.error().code() != ErrorCode::kCaptureBadFrame) return read.error();
      accounting_.skip_stale(stale);  // once, as stale (not again as a sequence gap)
      const Admission a = accounting_.admit(raw, format_);
      if (a != Admission::kDeliverable) {
        bad_run_ += a == Admission::kBad ? 1 : 0;
        continue;
      }
      bad_run_ = 0;
      accounting_.count_delivered();
      CapturedFrame f;
      f.bytes = raw.bytes;
      f.format = format_;
      // The recording's own numbering from its first frame (continued across loops), not a count
      // from the first frame delivered: frames skipped before it (due while the daemon was still
      // starting) must not shift every later frame's sequence against the recording's.
      f.sequence = raw.sequence - first_sequence_;
      f.timestamp_ns = stamp;
      f.skipped_before = stale;
      return f;
    }
  }

  void release() override {}

  void stop() override {
    reader_.reset();
    stats_.connected = false;
  }

  const image::FrameFormat& format() const override { return format_; }
  const SourceStats& stats() const override { return stats_; }
  const char* name() const override { return config_.label.c_str(); }

 private:
  // The record at next_record_, wrapping to the first one when looping. False at the end.
  Result<bool> peek(RecordInfo& info) {
    TLV_ASSIGN_OR_RETURN(bool have, reader_->record_at(next_record_, info));
    if (have || !config_.loop) return have;
    ++passes_;
    next_record_ = reader_->first_record();
    return reader_->record_at(next_record_, info);
  }

  int64_t due_ns(const RecordInfo& info) const {
    // Offsets count from the recording's origin, shared by fingers recorded together: a second
    // camera's phase (its first frame at +7 ms) survives the replay.
    return start_ns_ + info.offset_ns + static_cast<int64_t>(passes_) * loop_span_ns_;
  }

  ReplayConfig config_;
  SourceStats stats_;
  FrameAccounting accounting_;
  std::optional<RecordingReader> reader_;
  image::FrameFormat format_;
  std::vector<uint8_t> buffer_;
  uint64_t next_record_ = 0;
  uint32_t passes_ = 0;
  uint64_t bad_run_ = 0;  // bad frames in a row
  uint32_t loop_sequences_ = 0;
  uint32_t first_sequence_ = 0;  // the recording's first frame's sequence
  int64_t loop_span_ns_ = 0;
  int64_t start_ns_ = 0;
};

}  // namespace

Result<std::unique_ptr<FrameSource>> make_replay_source(const ReplayConfig& config) {
  TLV_ENSURE(!config.path.empty(), ErrorCode::kInvalidArgument, "replay '%s': no recording path",
             config.label.c_str());
  TLV_ENSURE(config.warmup_frames <= kMaxWarmupFrames, ErrorCode::kInvalidArgument,
             "replay '%s': warmup_frames = %u is over %u", config.label.c_str(),
             config.warmup_frames, kMaxWarmupFrames);
  return std::unique_ptr<FrameSource>(new ReplaySource(config));
}

}  // namespace tlvlink::capture
