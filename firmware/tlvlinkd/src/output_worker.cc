#include "output_worker.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "clock.h"
#include "tlvlink/pipeline/contact_gate.h"
#include "tlvlink/stream/stages.h"

namespace tlvlink::daemon::internal {
namespace {

int64_t process_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

int64_t peak_rss_kb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

double pct(int64_t cpu_ns, int64_t wall_ns) {
  return wall_ns > 0 ? 100.0 * static_cast<double>(cpu_ns) / static_cast<double>(wall_ns) : 0;
}

}  // namespace

// The stages up to the heads are the stream's (stage_ns, named in the Hello); write and total
// are the daemon's own.
static_assert(stream::kStageNames.size() == static_cast<size_t>(kHeads) + 1,
              "the stream's stages are the first ones");

const char* stage_name(int32_t s) {
  if (s >= 0 && s <= kHeads) return stream::kStageNames[static_cast<size_t>(s)];
  return s == kWrite ? "write" : s == kTotal ? "total" : "?";
}

OutputWorker::OutputWorker(std::vector<OutputSink*> sinks, const OutputNames& names,
                           OutputQueue& queue,
                           const std::vector<std::unique_ptr<CaptureWorker>>& captures,
                           const InferenceWorker& inference, std::vector<FrameRing*> rings,
                           int32_t status_interval_ms, bool status_line,
                           const std::atomic<bool>& stop)
    : sinks_(std::move(sinks)),
      names_(names),
      queue_(queue),
      captures_(captures),
      inference_(inference),
      rings_(std::move(rings)),
      interval_ms_(status_interval_ms),
      status_line_(status_line),
      stop_(stop),
      last_(captures.size()) {}

void OutputWorker::account(const pipeline::FramePrediction& p, int64_t written_ns) {
  const pipeline::FrameTimes& t = p.times;
  const auto add = [&](Stage s, int64_t from, int64_t to) {
    if (from > 0 && to >= from) latency_[s].add(to - from);
  };
  add(kDequeue, t.capture_ns, t.dequeued_ns);
  add(kDecode, t.dequeued_ns, t.decoded_ns);
  add(kQueueWait, t.decoded_ns, t.decoded_ns > 0 && t.gated_ns > 0 ? t.gated_ns : 0);
  if (p.encoder_ran) {
    add(kPreprocess, t.gated_ns, t.preprocessed_ns);
    add(kEncoder, t.preprocessed_ns, t.inferred_ns);
    add(kHeads, t.inferred_ns, t.heads_ns);
    add(kWrite, t.heads_ns, written_ns);
  } else {
    add(kWrite, t.gated_ns, written_ns);
  }
  add(kTotal, t.capture_ns, written_ns);
  if (p.sensor >= 0 && static_cast<size_t>(p.sensor) < last_.size())
    last_[static_cast<size_t>(p.sensor)] = p;
}

RunTotals OutputWorker::collect(int64_t now_ns) const {
  RunTotals r;
  const int64_t wall = now_ns - start_ns_;
  r.seconds = static_cast<double>(wall) * 1e-9;
  for (size_t i = 0; i < captures_.size(); ++i) {
    const CaptureSnapshot c = captures_[i]->snapshot();
    r.drops_stale += c.source.skipped_stale;
    r.drops_sequence += c.source.dropped;
    r.bad_frames +=
        c.source.flagged_error + c.source.empty + c.source.short_frames + c.source.bad_mjpeg;
    r.decode_errors += c.decode_errors;
    r.drops_queue += rings_[i]->dropped();
    r.sensor_cpu_pct[i] = pct(c.cpu_ns, wall);
    r.sensor_fps[i] = c.source.measured_fps;
    r.sensor_frames[i] = c.source.delivered;
    r.sensor_disconnects[i] = c.source.disconnects;
    r.sensor_reconnects[i] = c.source.reconnects;
    r.sensor_reopen_failures[i] = c.source.reconnect_attempts;
    r.sensor_outage_s[i] = static_cast<double>(c.source.outage_ns) * 1e-9;
    r.sensors = static_cast<int32_t>(i + 1);
  }
  const InferenceSnapshot inf = inference_.snapshot();
  r.sensor_encoded = inf.counters.sensor_encoder_runs;
  r.sensor_gated = inf.counters.sensor_gated;
  r.frames = inf.counters.frames;
  r.encoded = inf.counters.encoder_runs;
  r.gated = inf.counters.gated;
  r.inference_errors = inf.errors;
  r.inference_cpu_pct = pct(inf.cpu_ns, wall);
  r.output_cpu_pct = pct(thread_cpu_ns(cpu_clock_), wall);
  r.grasps = grasps_;
  r.grasps_not_computed = grasps_not_computed_;
  r.drops_output = queue_.dropped();
  if (images_ != nullptr) {
    r.frame_images = true;
    r.images_sent = images_->sent();
    r.drops_image = images_->busy();
    if (images_->copies() > 0)
      r.image_copy_us =
          static_cast<double>(images_->copy_ns()) / static_cast<double>(images_->copies()) * 1e-3;
    if (images_->encodes() > 0)
      r.image_encode_ms = static_cast<double>(images_->encode_ns()) /
                          static_cast<double>(images_->encodes()) * 1e-6;
  }
  for (const OutputSink* sink : sinks_) r.write_errors += sink->failed();
  r.t_ns = now_ns;
  r.process_cpu_pct = pct(process_cpu_ns() - start_cpu_ns_, wall);
  for (int32_t s = 0; s < kStages; ++s) {
    r.p50_ms[static_cast<size_t>(s)] =
        static_cast<double>(latency_[static_cast<size_t>(s)].percentile_ns(0.5)) * 1e-6;
    r.p99_ms[static_cast<size_t>(s)] =
        static_cast<double>(latency_[static_cast<size_t>(s)].percentile_ns(0.99)) * 1e-6;
    r.max_ms[static_cast<size_t>(s)] =
        static_cast<double>(latency_[static_cast<size_t>(s)].max_ns()) * 1e-6;
  }
  r.peak_rss_kb = peak_rss_kb();
  return r;
}

void OutputWorker::report(int64_t now_ns, bool final) {
  const RunTotals r = collect(now_ns);
  for (OutputSink* sink : sinks_) sink->stats(r, final);
  if (final) final_ = r;
}

void OutputWorker::status_line(int64_t now_ns) {
  const RunTotals r = collect(now_ns);
  char line[512];
  int n = std::snprintf(line, sizeof line, "\r[%6.1fs]", r.seconds);
  for (size_t i = 0; i < static_cast<size_t>(r.sensors) && n < static_cast<int>(sizeof line); ++i) {
    const pipeline::FramePrediction& p = last_[i];
    n += std::snprintf(
        line + n, sizeof line - static_cast<size_t>(n), " %s %.1ffps %s", names_.sensors[i].c_str(),
        r.sensor_fps[i],
        p.contact_state == static_cast<uint8_t>(pipeline::ContactState::kContact) ? "touch" : "-");
  }
  if (n < static_cast<int>(sizeof line)) {
    n += std::snprintf(line + n, sizeof line - static_cast<size_t>(n),
                       " | p50 %.1f p99 %.1f ms | grasps %llu", r.p50_ms[kTotal], r.p99_ms[kTotal],
                       static_cast<unsigned long long>(r.grasps));
  }
  if (last_grasp_p_ >= 0 && n < static_cast<int>(sizeof line)) {
    n += std::snprintf(line + n, sizeof line - static_cast<size_t>(n), " (last p=%.2f)",
                       static_cast<double>(last_grasp_p_));
  }
  // The first sensor in contact: its top label per head.
  for (const pipeline::FramePrediction& p : last_) {
    if (!p.encoder_ran || n >= static_cast<int>(sizeof line)) continue;
    for (int32_t k = 0; k < p.head_count && n < static_cast<int>(sizeof line); ++k) {
      const pipeline::HeadProbabilities& h = p.heads[static_cast<size_t>(k)];
      const OutputNames::Head& names = names_.heads[static_cast<size_t>(h.head)];
      n += std::snprintf(line + n, sizeof line - static_cast<size_t>(n), " %s:%s",
                         names.name.c_str(), names.labels[static_cast<size_t>(h.top)].c_str());
    }
    break;
  }
  const uint64_t drops = r.drops_stale + r.drops_queue + r.drops_output;
  if (n < static_cast<int>(sizeof line))
    n += std::snprintf(line + n, sizeof line - static_cast<size_t>(n), " | drops %llu\x1b[K",
                       static_cast<unsigned long long>(drops));
  [[maybe_unused]] const ssize_t w =
      ::write(STDERR_FILENO, line, std::min(sizeof line - 1, static_cast<size_t>(n)));
}

void OutputWorker::run() {
  cpu_clock_ = this_thread_cpu_clock();
  start_ns_ = board_clock_ns();
  start_cpu_ns_ = process_cpu_ns();
  int64_t next_report = start_ns_ + static_cast<int64_t>(interval_ms_) * 1'000'000;
  OutputRecord record;
  for (;;) {
    const int64_t now = board_clock_ns();
    const auto wait_ms =
        static_cast<int32_t>(std::clamp<int64_t>((next_report - now) / 1'000'000, 0, interval_ms_));
    if (queue_.pop(record, wait_ms)) {
      const int64_t written = board_clock_ns();
      if (auto* p = std::get_if<pipeline::FramePrediction>(&record)) {
        p->times.written_ns = written;
        account(*p, written);
      } else if (auto* g = std::get_if<pipeline::GraspPrediction>(&record)) {
        (g->computed ? grasps_ : grasps_not_computed_) += 1;
        if (g->computed) last_grasp_p_ = g->probability;
      }
      for (OutputSink* sink : sinks_) sink->record(record, written);
    }
    const int64_t t = board_clock_ns();
    if (t >= next_report) {
      report(t, false);
      if (status_line_) status_line(t);
      next_report = t + static_cast<int64_t>(interval_ms_) * 1'000'000;
    }
    if (stop_.load() && queue_.size() == 0) break;
  }
  if (status_line_) [[maybe_unused]]
    ssize_t w = ::write(STDERR_FILENO, "\n", 1);
  report(board_clock_ns(), true);
  for (OutputSink* sink : sinks_) sink->close();
  // The summary record itself (and what close() flushed) may have failed too: the totals the
  // daemon prints and exits on count every record lost, as each sink's problem() does.
  final_.write_errors = 0;
  for (const OutputSink* sink : sinks_) final_.write_errors += sink->failed();
}

RunTotals OutputWorker::totals() const { return final_; }

bool OutputWorker::outputs_closed() const {
  for (const OutputSink* sink : sinks_)
    if (!sink->closed()) return false;
  return !sinks_.empty();
}

void OutputWorker::print_summary(std::FILE* out) const {
  const RunTotals& r = final_;
  std::fprintf(out,
               "tlvlinkd: %.1f s, %llu frames (%llu encoded, %llu gated), %llu grasps predicted, "
               "%llu not computed\n",
               r.seconds, static_cast<unsigned long long>(r.frames),
               static_cast<unsigned long long>(r.encoded), static_cast<unsigned long long>(r.gated),
               static_cast<unsigned long long>(r.grasps),
               static_cast<unsigned long long>(r.grasps_not_computed));
  std::fprintf(out,
               "  drops: stale %llu, sequence gaps %llu, queue %llu, output %llu, write errors "
               "%llu; bad frames %llu, decode errors %llu\n",
               static_cast<unsigned long long>(r.drops_stale),
               static_cast<unsigned long long>(r.drops_sequence),
               static_cast<unsigned long long>(r.drops_queue),
               static_cast<unsigned long long>(r.drops_output),
               static_cast<unsigned long long>(r.write_errors),
               static_cast<unsigned long long>(r.bad_frames),
               static_cast<unsigned long long>(r.decode_errors));
  if (r.frame_images) {
    std::fprintf(
        out,
        "  frame images: %llu sent, %llu not sent (image_busy: encoder or link busy); per image "
        "%.1f us copying on the inference thread, %.2f ms encoding and posting\n",
        static_cast<unsigned long long>(r.images_sent),
        static_cast<unsigned long long>(r.drops_image), r.image_copy_us, r.image_encode_ms);
  }
  // Every output that lost records, or whose reader left, with the path and the reason.
  for (size_t i = 0; i < sinks_.size(); ++i) {
    std::string problem = sinks_[i]->problem();
    if (problem.empty() && sinks_[i]->failed() > 0) {
      problem = "output " + std::to_string(i + 1) + ": " + std::to_string(sinks_[i]->failed()) +
                " record(s) not sent";
    }
    if (!problem.empty()) std::fprintf(out, "  %s\n", problem.c_str());
  }
  for (int32_t i = 0; i < r.sensors; ++i) {
    const size_t k = static_cast<size_t>(i);
    if (r.sensor_disconnects[k] == 0) continue;
    std::fprintf(
        out,
        "  camera %s: lost %llu, back %llu, reopen attempts failed %llu, %.2f s without camera\n",
        names_.sensors[k].c_str(), static_cast<unsigned long long>(r.sensor_disconnects[k]),
        static_cast<unsigned long long>(r.sensor_reconnects[k]),
        static_cast<unsigned long long>(r.sensor_reopen_failures[k]), r.sensor_outage_s[k]);
  }
  std::fprintf(out, "  latency ms (p50 / p99 / max):");
  for (int32_t s = 0; s < kStages; ++s) {
    std::fprintf(out, " %s %.2f/%.2f/%.2f", stage_name(s), r.p50_ms[static_cast<size_t>(s)],
                 r.p99_ms[static_cast<size_t>(s)], r.max_ms[static_cast<size_t>(s)]);
  }
  std::fprintf(out, "\n  cpu %%: process %.1f, inference %.1f, output %.1f, sensors",
               r.process_cpu_pct, r.inference_cpu_pct, r.output_cpu_pct);
  for (int32_t i = 0; i < r.sensors; ++i)
    std::fprintf(out, " %.1f", r.sensor_cpu_pct[static_cast<size_t>(i)]);
  std::fprintf(out, "; peak RSS %.1f MB\n", static_cast<double>(r.peak_rss_kb) / 1024.0);
}

}  // namespace tlvlink::daemon::internal
