// The sweep's CSV, JSON, SVG and terminal table (sweep.h).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <thread>

#include "tlvlink/io/format.h"
#include "tlvlink/quantize/plot.h"
#include "tlvlink/quantize/report.h"
#include "tlvlink/quantize/sweep.h"

namespace tlvlink::quantize {

std::string sweep_csv(const SweepResult& result) {
  std::string s =
      "model,name,resolution,mmac,variant,precision,weights,method,bias_correction_frames,threads,"
      "int8_ops,fp32_ops,"
      "bytes,cosine_mean,cosine_min,one_minus_cosine,sqnr_db,max_abs,latency_median_ms,"
      "latency_p90_ms,latency_min_ms\n";
  char line[512];
  for (const SweepRow& r : result.rows) {
    std::snprintf(
        line, sizeof(line),
        "%s,%s,%s,%.2f,%s,%s,%s,%s,%zu,%d,%zu,%zu,%zu,%.7f,%.7f,%.3e,%s,%.5g,%.4f,%.4f,%.4f\n",
        csv_cell(r.model).c_str(), csv_cell(r.model_name).c_str(), r.resolution.c_str(), r.mmac,
        r.variant.c_str(), r.precision.c_str(), r.weights.c_str(), r.method.c_str(),
        r.bias_correction_frames, r.threads, r.int8_ops, r.fp32_ops, r.bytes, r.cos_mean, r.cos_min,
        1.0 - r.cos_mean, format_db(r.sqnr_db).c_str(), r.max_abs, r.latency.median, r.latency.p90,
        r.latency.min);
    s += line;
  }
  return s;
}

nlohmann::json sweep_json(const SweepOptions& o, const SweepResult& result) {
  nlohmann::json j;
  j["load_average_1min"] = {{"start", result.load_before}, {"end", result.load_after}};
  j["timing"] = "interleaved blocks: per round, every variant gets 1 untimed + up to " +
                std::to_string(bench::kTimedPerBlock) + " timed inferences";
  j["runs"] = o.runs;
  j["warmup"] = o.warmup;
  j["executor"] = "xnnpack";
  j["error_reference"] = "fp32 model on the reference executor, held-out frames";
  j["calibration"] = {{"data", o.data.paths},
                      {"frames", o.data.calib_count},
                      {"heldout_frames", o.data.heldout_count},
                      {"seed", o.data.seed},
                      {"percentile", o.percentile}};
  j["rows"] = nlohmann::json::array();
  for (const SweepRow& r : result.rows) {
    j["rows"].push_back({{"model", r.model},
                         {"name", r.model_name},
                         {"resolution", r.resolution},
                         {"mmac", r.mmac},
                         {"variant", r.variant},
                         {"precision", r.precision},
                         {"weights", r.weights},
                         {"method", r.method},
                         {"bias_correction_frames", r.bias_correction_frames},
                         {"threads", r.threads},
                         {"int8_ops", r.int8_ops},
                         {"fp32_ops", r.fp32_ops},
                         {"bytes", r.bytes},
                         {"cosine_mean", r.cos_mean},
                         {"cosine_min", r.cos_min},
                         {"sqnr_db", json_number(r.sqnr_db)},
                         {"max_abs", r.max_abs},
                         {"latency_median_ms", r.latency.median},
                         {"latency_p90_ms", r.latency.p90},
                         {"latency_min_ms", r.latency.min}});
  }
  return j;
}

std::string sweep_svg(const SweepOptions& o, const SweepResult& result) {
  const std::vector<SweepRow>& rows = result.rows;
  PlotSpec spec;
  spec.title =
      "Embedding error against run time (XNNPACK, median of " + std::to_string(o.runs) + " runs)";
  spec.x_label = "latency per frame, ms (median)";
  spec.y_label = "1 - cosine(embedding, fp32 reference), held-out mean";
  for (const SweepVariant& v : result.variants) spec.series.push_back(v.name);
  for (const std::string& m : o.models) {
    const std::string name = std::filesystem::path(m).filename().string();
    spec.shapes.push_back(name.size() > 34 ? name.substr(0, 31) + "..." : name);
  }
  for (int t : o.threads)
    spec.fills.push_back(std::to_string(t) + (t == 1 ? " thread" : " threads"));
  // Floor one decade below the smallest int8 error, so fp32 (~0 error) sits just under them.
  double smallest = 1;
  for (const SweepRow& r : rows)
    if (r.precision == "int8" && 1.0 - r.cos_mean > 0)
      smallest = std::min(smallest, 1.0 - r.cos_mean);
  spec.y_floor = std::pow(10.0, std::floor(std::log10(smallest)) - 1);
  // A log latency axis when the spread is wide (resolutions, or a loaded machine's outliers).
  double fastest = 0, slowest = 0;
  for (const SweepRow& r : rows) {
    fastest = fastest == 0 ? r.latency.median : std::min(fastest, r.latency.median);
    slowest = std::max(slowest, r.latency.median);
  }
  spec.log_x = fastest > 0 && slowest / fastest > 20;
  std::vector<PlotPoint> points;
  for (const SweepRow& r : rows) {
    const size_t fill = static_cast<size_t>(
        std::find(o.threads.begin(), o.threads.end(), r.threads) - o.threads.begin());
    points.push_back(
        {r.latency.median, std::max(0.0, 1.0 - r.cos_mean), r.variant_index, r.model_index, fill});
  }
  return error_latency_svg(points, spec);
}

std::string sweep_table(const SweepOptions& o, const SweepResult& result) {
  // The variant column is as wide as the longest name, so the figures line up.
  int width = 7;
  for (const SweepRow& r : result.rows) width = std::max(width, static_cast<int>(r.variant.size()));
  std::string s;
  tools::appendf(s, "%-24s %-9s %-*s %3s %9s %9s %8s %10s %10s\n", "model", "res", width, "variant",
                 "thr", "cos mean", "cos min", "SQNR dB", "median ms", "p90 ms");
  for (const SweepRow& r : result.rows) {
    const std::string name = std::filesystem::path(r.model).filename().string();
    tools::appendf(s, "%-24.24s %-9s %-*s %3d %9.5f %9.5f %8s %10.3f %10.3f\n", name.c_str(),
                   r.resolution.c_str(), width, r.variant.c_str(), r.threads, r.cos_mean, r.cos_min,
                   format_db(r.sqnr_db).c_str(), r.latency.median, r.latency.p90);
  }
  tools::appendf(s, "load average (1 min) %.2f at the start, %.2f at the end, on %u cores\n",
                 result.load_before, result.load_after, std::thread::hardware_concurrency());
  tools::appendf(s, "wrote %s/sweep.{csv,json,svg}%s\n", o.out_dir.c_str(),
                 result.png ? " and sweep.png" : " (no rsvg-convert: no PNG)");
  return s;
}

}  // namespace tlvlink::quantize
