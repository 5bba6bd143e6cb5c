#include "jsonl_sink.h"

#include "board_hello.h"
#include "tlvlink/clock.h"

namespace tlvlink::daemon::internal {
namespace {

// The run report only the daemon writes (the stream's Stats carries the counts a host needs):
// totals, drops by the daemon's causes, CPU per thread, camera outages, latency percentiles per
// stage, peak RSS. A key of the stats line, after the message's keys.
void run_report(stream::LineBuffer& l, const RunTotals& r) {
  l.printf(
      ",\"daemon\":{\"t_ns\":%lld,\"uptime_s\":%.3f,\"frames\":%llu,\"encoded\":%llu,"
      "\"gated\":%llu,\"grasps\":%llu,\"grasps_not_computed\":%llu,\"drops\":{\"stale\":%llu,"
      "\"sequence_gaps\":%llu,\"queue\":%llu,\"output\":%llu,\"bad_frames\":%llu,"
      "\"decode_errors\":%llu,\"write_errors\":%llu},\"cpu_pct\":{\"process\":%.1f,\"inference\":%."
      "1f,\"output\":%.1f,\"sensors\":[",
      static_cast<long long>(r.t_ns), r.seconds, static_cast<unsigned long long>(r.frames),
      static_cast<unsigned long long>(r.encoded), static_cast<unsigned long long>(r.gated),
      static_cast<unsigned long long>(r.grasps),
      static_cast<unsigned long long>(r.grasps_not_computed),
      static_cast<unsigned long long>(r.drops_stale),
      static_cast<unsigned long long>(r.drops_sequence),
      static_cast<unsigned long long>(r.drops_queue),
      static_cast<unsigned long long>(r.drops_output),
      static_cast<unsigned long long>(r.bad_frames),
      static_cast<unsigned long long>(r.decode_errors),
      static_cast<unsigned long long>(r.write_errors), r.process_cpu_pct, r.inference_cpu_pct,
      r.output_cpu_pct);
  const size_t n = static_cast<size_t>(r.sensors);
  for (size_t i = 0; i < n; ++i) l.printf("%s%.1f", i ? "," : "", r.sensor_cpu_pct[i]);
  l.printf("]},\"fps\":[");
  for (size_t i = 0; i < n; ++i) l.printf("%s%.2f", i ? "," : "", r.sensor_fps[i]);
  // Camera outages per sensor: disconnects (outages begun), reconnects (ended by a reopen),
  // reopen attempts that failed, seconds without a camera.
  l.printf("],\"camera\":{\"disconnects\":[");
  for (size_t i = 0; i < n; ++i)
    l.printf("%s%llu", i ? "," : "", static_cast<unsigned long long>(r.sensor_disconnects[i]));
  l.printf("],\"reconnects\":[");
  for (size_t i = 0; i < n; ++i)
    l.printf("%s%llu", i ? "," : "", static_cast<unsigned long long>(r.sensor_reconnects[i]));
  l.printf("],\"reopen_failures\":[");
  for (size_t i = 0; i < n; ++i)
    l.printf("%s%llu", i ? "," : "", static_cast<unsigned long long>(r.sensor_reopen_failures[i]));
  l.printf("],\"outage_s\":[");
  for (size_t i = 0; i < n; ++i) l.printf("%s%.3f", i ? "," : "", r.sensor_outage_s[i]);
  l.printf("]},\"latency_ms\":{");
  for (int32_t s = 0; s < kStages; ++s) {
    l.printf("%s\"%s\":{\"p50\":%.3f,\"p99\":%.3f,\"max\":%.3f}", s ? "," : "", stage_name(s),
             r.p50_ms[static_cast<size_t>(s)], r.p99_ms[static_cast<size_t>(s)],
             r.max_ms[static_cast<size_t>(s)]);
  }
  l.printf("},\"peak_rss_mb\":%.1f}", static_cast<double>(r.peak_rss_kb) / 1024.0);
}

}  // namespace

JsonlSink::JsonlSink(JsonlWriter writer, std::unique_ptr<stream::HelloBuilder> hello,
                     bool detected_grasps)
    : writer_(std::move(writer)), hello_(std::move(hello)), mapper_(detected_grasps) {
  stream::LineBuffer& l = writer_.start_line();
  stream::json_begin(l, protocol::MessageType::kHello, header(board_clock_ns()));
  stream::json_fields(l, hello_->hello(), protocol::schema_hash());
  stream::json_end(l);
  writer_.write_line();
}

void JsonlSink::record(const OutputRecord& record, int64_t written_ns) {
  stream::LineBuffer& l = writer_.start_line();
  if (const auto* p = std::get_if<pipeline::FramePrediction>(&record)) {
    stream::json_begin(l, protocol::MessageType::kFramePrediction, header(written_ns));
    stream::json_fields(l, mapper_.frame(*p), &hello_->hello());
    if (p->embedding_dim > 0) {  // `embedding = true`: the encoder's int8 output too (tests/hil)
      l.key("int8");
      l.put('[');
      for (int32_t i = 0; i < p->int8_count; ++i)
        l.printf("%s%d", i > 0 ? "," : "", p->int8_values[static_cast<size_t>(i)]);
      l.put(']');
    }
  } else if (const auto* g = std::get_if<pipeline::GraspPrediction>(&record)) {
    stream::json_begin(l, protocol::MessageType::kGraspPrediction, header(written_ns));
    stream::json_fields(l, mapper_.grasp(*g));
  } else {
    const EventRecord& e = std::get<EventRecord>(record);
    stream::json_begin(l, protocol::MessageType::kError, header(written_ns));
    stream::json_fields(l, stream::MessageMapper::event(e.error, e.sensor, e.text.data()));
  }
  stream::json_end(l);
  writer_.write_line();
}

void JsonlSink::stats(const RunTotals& r, bool final) {
  stream::LineBuffer& l = writer_.start_line();
  stream::json_begin(l, protocol::MessageType::kStats, header(r.t_ns));
  stream::json_fields(l, mapper_.stats(stream_totals(r)));
  l.printf(",\"final\":%s", final ? "true" : "false");  // the run's summary, at its end
  run_report(l, r);
  stream::json_end(l);
  writer_.write_line();
}

}  // namespace tlvlink::daemon::internal
