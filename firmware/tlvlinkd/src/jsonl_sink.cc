#include "jsonl_sink.h"

namespace tlvlink::daemon::internal {

void JsonlSink::stats(const RunTotals& r, bool final) {
  LineBuffer& l = writer_.scratch();
  l.clear();
  l.printf(
      "{\"type\":\"%s\",\"t_ns\":%lld,\"uptime_s\":%.3f,\"frames\":%llu,\"encoded\":%llu,"
      "\"gated\":%llu,\"grasps\":%llu,\"grasps_not_computed\":%llu,\"drops\":{\"stale\":%llu,"
      "\"sequence_gaps\":%llu,\"queue\":%llu,\"output\":%llu,\"bad_frames\":%llu,"
      "\"decode_errors\":%llu,\"write_errors\":%llu},\"cpu_pct\":{\"process\":%.1f,\"inference\":%."
      "1f,\"output\":%.1f,\"sensors\":[",
      final ? "summary" : "stats", static_cast<long long>(r.t_ns), r.seconds,
      static_cast<unsigned long long>(r.frames), static_cast<unsigned long long>(r.encoded),
      static_cast<unsigned long long>(r.gated), static_cast<unsigned long long>(r.grasps),
      static_cast<unsigned long long>(r.grasps_not_computed),
      static_cast<unsigned long long>(r.drops_stale),
      static_cast<unsigned long long>(r.drops_sequence),
      static_cast<unsigned long long>(r.drops_queue),
      static_cast<unsigned long long>(r.drops_output),
      static_cast<unsigned long long>(r.bad_frames),
      static_cast<unsigned long long>(r.decode_errors),
      static_cast<unsigned long long>(r.write_errors), r.process_cpu_pct, r.inference_cpu_pct,
      r.output_cpu_pct);
  for (size_t i = 0; i < static_cast<size_t>(r.sensors); ++i)
    l.printf("%s%.1f", i ? "," : "", r.sensor_cpu_pct[i]);
  l.printf("]},\"fps\":[");
  for (size_t i = 0; i < static_cast<size_t>(r.sensors); ++i)
    l.printf("%s%.2f", i ? "," : "", r.sensor_fps[i]);
  // Camera outages per sensor: disconnects (outages begun), reconnects (ended by a reopen),
  // reopen attempts that failed, seconds without a camera.
  const size_t n = static_cast<size_t>(r.sensors);
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
  l.printf("},\"peak_rss_mb\":%.1f}\n", static_cast<double>(r.peak_rss_kb) / 1024.0);
  writer_.write_line(l);
}

}  // namespace tlvlink::daemon::internal
