// tlvlink quantize-sweep: error against run time. For each model and variant (fp32; int8 with
// per-tensor weights; int8 per-channel with each calibration method) the embedding error on
// held-out frames and the latency measured by the XNNPACK executor in the same run, at each
// thread count. Writes sweep.csv, sweep.json and sweep.svg (+ sweep.png when rsvg-convert is
// installed).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>

#include "cli/common.h"
#include "cli/op_stats.h"
#include "cli/quantize_data.h"
#include "cli/quantize_options.h"
#include "cli/quantize_plot.h"
#include "cli/quantize_report.h"
#include "tlvlink/io/file.h"
#include "tlvlink/quantize/bias_correction.h"
#include "tlvlink/quantize/layer_error.h"
#include "tlvlink/quantize/quantizer.h"

namespace tlvlink::cli {
namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

struct SweepFlags {
  std::vector<std::string> models;
  QuantizeCommonFlags common;
  std::string out_dir;
  std::vector<int> threads = {1, 2};
  std::vector<std::string> methods = {"minmax", "ema", "percentile", "entropy", "mse"};
  std::vector<std::string> keep_float;  // non-empty: one more row, mixed precision
  double percentile = 99.99;
  int bias_correction_frames = 64;  // 0: off
  int runs = 50, warmup = 5;
  bool quiet = false;
};

struct Variant {
  std::string name;
  bool fp32 = false;
  quantize::WeightGranularity weights = quantize::WeightGranularity::kPerChannel;
  quantize::CalibrationMethod method = quantize::CalibrationMethod::kMinMax;
  std::vector<std::string> keep_float;
  bool bias_correction = true;  // when the sweep corrects at all (--bias-correction > 0)
};

struct Latency {
  double median = 0, p90 = 0, min = 0;
};

struct Row {
  std::string model, model_name, resolution, variant, precision, weights, method;
  size_t bias_correction_frames = 0;
  size_t model_index = 0, variant_index = 0;
  double mmac = 0;
  int threads = 1;
  size_t int8_ops = 0, fp32_ops = 0, bytes = 0;
  double cos_mean = 0, cos_min = 0, sqnr_db = 0, max_abs = 0;
  Latency latency;
};

// Nearest-rank percentile of sorted samples (as bench.cc).
double percentile_of(const std::vector<double>& sorted, double p) {
  const auto rank = static_cast<size_t>(std::ceil(p / 100.0 * static_cast<double>(sorted.size())));
  return sorted[std::clamp<size_t>(rank, 1, sorted.size()) - 1];
}

// One timed executor per (variant, thread count) of a model.
struct Timed {
  std::unique_ptr<Executor> exec;
  std::vector<double> samples;
  size_t row = 0;
};

Result<Timed> make_timed(const Model& m, int threads, const std::vector<float>& frame, int warmup) {
  ExecutorOptions o;
  o.threads = threads;
  Timed t;
  TLV_ASSIGN_OR_RETURN(t.exec, make_xnnpack_executor(m, o));
  std::memcpy(t.exec->input(0).data(), frame.data(), t.exec->input(0).size());
  for (size_t i = 1; i < m.graph().inputs.size(); ++i)
    std::memset(t.exec->input(i).data(), 0, t.exec->input(i).size());
  for (int i = 0; i <= warmup; ++i) TLV_TRY(t.exec->invoke());  // first inference + warm-up
  return t;
}

// bench.cc's figures (first inference and `warmup` untimed, then median / p90 / min of `runs`
// single inferences), with the variants interleaved in blocks: each round gives every executor
// one untimed inference (its thread pool wakes up) and then kTimedPerBlock timed ones. A burst of
// load on a shared machine then hits every variant alike instead of whichever ran during it,
// while a multi-threaded pool stays warm within its block (one inference per turn would time
// the wake-up of a cold worker thread, not the inference).
constexpr int kTimedPerBlock = 10;

Status time_interleaved(std::vector<Timed>& timed, int runs) {
  for (int done = 0; done < runs; done += kTimedPerBlock) {
    const int block = std::min(kTimedPerBlock, runs - done);
    for (Timed& t : timed) {
      TLV_TRY(t.exec->invoke());
      for (int i = 0; i < block; ++i) {
        const auto t0 = Clock::now();
        TLV_TRY(t.exec->invoke());
        t.samples.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      }
    }
  }
  return {};
}

Latency latency_of(std::vector<double> samples) {
  std::sort(samples.begin(), samples.end());
  return Latency{percentile_of(samples, 50), percentile_of(samples, 90), samples.front()};
}

// 1-minute load average from /proc/loadavg (0 if unavailable): the sweep reports it, since
// latency on a shared machine depends on it.
double load_average() {
  double load = 0;
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = 0;
    std::fclose(f);
  }
  return load;
}

std::vector<Variant> variants(const std::vector<quantize::CalibrationMethod>& methods,
                              const std::vector<std::string>& keep_float, bool bias_correction) {
  std::vector<Variant> v;
  v.push_back({"fp32", true, {}, {}, {}});
  // What bias correction does on its own: the main method's per-channel row without it.
  quantize::CalibrationMethod main = methods.front();
  for (quantize::CalibrationMethod c : methods)
    if (c == quantize::CalibrationMethod::kPercentile) main = c;
  if (bias_correction) {
    v.push_back({std::string("int8 per-channel ") + quantize::calibration_method_name(main) +
                     " without bias correction",
                 false, quantize::WeightGranularity::kPerChannel, main, {}, false});
  }
  v.push_back({std::string("int8 per-tensor ") + quantize::calibration_method_name(methods.front()),
               false, quantize::WeightGranularity::kPerTensor, methods.front(), {}});
  for (quantize::CalibrationMethod m : methods)
    v.push_back({std::string("int8 per-channel ") + quantize::calibration_method_name(m), false,
                 quantize::WeightGranularity::kPerChannel, m, {}});
  if (!keep_float.empty()) {
    std::string list;
    for (const std::string& k : keep_float) list += (list.empty() ? "" : ",") + k;
    // Percentile (quantize's default) when swept, else the first method.
    v.push_back({std::string("int8 per-channel ") + quantize::calibration_method_name(main) +
                     " + fp32 " + list,
                 false, quantize::WeightGranularity::kPerChannel, main, keep_float});
  }
  for (Variant& x : v) x.bias_correction = x.bias_correction && bias_correction && !x.fp32;
  return v;
}

Status sweep_model(const SweepFlags& f, size_t index, const std::vector<Variant>& vars,
                   std::vector<Row>& rows) {
  const std::string& path = f.models[index];
  TLV_ASSIGN_OR_RETURN(auto model, load_model(path));
  const Model& fp32 = *model;
  const InputSpec& spec = fp32.metadata().input;
  std::fprintf(stderr, "quantize-sweep: %s (%dx%d)\n", path.c_str(), spec.height, spec.width);
  auto data = load_calib_data(f.common.data_options(!f.quiet), spec);
  if (!data.ok()) return data.error().with_context("calibration data for %s", path.c_str());
  TLV_ENSURE(!data->heldout.empty(), ErrorCode::kInvalidArgument,
             "the sweep needs held-out frames (--heldout-count > 0 and data with more than the "
             "calibration frames)");
  TLV_ASSIGN_OR_RETURN(auto stats, calibrate_with_progress(fp32, data->calibration, f.common, !f.quiet));
  TLV_ASSIGN_OR_RETURN(auto reference, quantize::embeddings(fp32, data->heldout));
  const double mmac = static_cast<double>(graph_stats(fp32.graph()).macs) / 1e6;
  // Quantize every variant and measure its error first; then time them all together.
  std::vector<std::unique_ptr<Model>> models;  // keeps the int8 models alive for their executors
  std::vector<Timed> timed;
  const size_t first_row = rows.size();
  for (size_t vi = 0; vi < vars.size(); ++vi) {
    const Variant& v = vars[vi];
    std::unique_ptr<Model> int8;
    Row base;
    base.model = path;
    base.model_name = std::string(fp32.metadata().name);
    base.resolution = std::to_string(spec.height) + "x" + std::to_string(spec.width);
    base.mmac = mmac;
    base.model_index = index;
    base.variant_index = vi;
    base.variant = v.name;
    base.precision = v.fp32 ? "fp32" : "int8";
    base.weights = v.fp32 ? "-" : quantize::weight_granularity_name(v.weights);
    base.method = v.fp32 ? "-" : quantize::calibration_method_name(v.method);
    base.bytes = fp32.bytes().size();
    base.fp32_ops = fp32.graph().operators.size();
    if (!v.fp32) {
      quantize::CalibrationOptions c;
      c.method = v.method;
      c.percentile = f.percentile;
      quantize::QuantizerOptions qo;
      qo.weights = v.weights;
      qo.keep_float = v.keep_float;
      const std::vector<quantize::TensorRange> ranges = quantize::select_ranges(stats, c);
      quantize::QuantizedModel q;
      if (v.bias_correction) {
        quantize::BiasCorrectionOptions bo;
        bo.max_frames = static_cast<size_t>(f.bias_correction_frames);
        TLV_ASSIGN_OR_RETURN(auto corrected,
                             quantize::correct_biases(fp32, ranges, qo, data->calibration, bo));
        base.bias_correction_frames = corrected.frames;
        q = std::move(corrected.model);
      } else {
        TLV_ASSIGN_OR_RETURN(q, quantize::quantize_model(fp32, ranges, qo));
      }
      const std::vector<std::byte> file = q.builder.finish();
      TLV_ASSIGN_OR_RETURN(int8, Model::load(file));
      base.bytes = file.size();
      base.int8_ops = q.int8_ops;
      base.fp32_ops = q.float_ops;
    }
    const Model& m = v.fp32 ? fp32 : *int8;
    // The deployed path: XNNPACK outputs against the fp32 reference executor.
    TLV_ASSIGN_OR_RETURN(auto out, quantize::embeddings(m, data->heldout, ExecutorKind::kXnnpack, 1));
    const quantize::ModelError e = quantize::compare_embeddings(reference, out);
    base.cos_mean = e.mean_cosine();
    base.cos_min = e.min_cosine();
    base.sqnr_db = e.embedding.sqnr_db();
    base.max_abs = e.embedding.max_abs;
    for (int t : f.threads) {
      Row r = base;
      r.threads = t;
      TLV_ASSIGN_OR_RETURN(Timed tm, make_timed(m, t, data->heldout.front(), f.warmup));
      tm.row = rows.size();
      timed.push_back(std::move(tm));
      rows.push_back(r);
    }
    if (int8) models.push_back(std::move(int8));
  }
  TLV_TRY(time_interleaved(timed, f.runs));
  for (Timed& t : timed) rows[t.row].latency = latency_of(t.samples);
  for (size_t i = first_row; i < rows.size(); ++i) {
    std::fprintf(stderr, "  %-50s %d thread(s): cosine %.5f, median %.3f ms\n", rows[i].variant.c_str(),
                 rows[i].threads, rows[i].cos_mean, rows[i].latency.median);
  }
  return {};
}

std::string csv_of(const std::vector<Row>& rows) {
  std::string s = "model,name,resolution,mmac,variant,precision,weights,method,bias_correction_frames,threads,int8_ops,fp32_ops,"
                  "bytes,cosine_mean,cosine_min,one_minus_cosine,sqnr_db,max_abs,latency_median_ms,"
                  "latency_p90_ms,latency_min_ms\n";
  char line[512];
  for (const Row& r : rows) {
    std::snprintf(line, sizeof(line), "%s,%s,%s,%.2f,%s,%s,%s,%s,%zu,%d,%zu,%zu,%zu,%.7f,%.7f,%.3e,%s,%.5g,%.4f,%.4f,%.4f\n",
                  csv_cell(r.model).c_str(), csv_cell(r.model_name).c_str(), r.resolution.c_str(), r.mmac,
                  r.variant.c_str(), r.precision.c_str(), r.weights.c_str(), r.method.c_str(),
                  r.bias_correction_frames, r.threads,
                  r.int8_ops, r.fp32_ops, r.bytes, r.cos_mean, r.cos_min, 1.0 - r.cos_mean,
                  format_db(r.sqnr_db).c_str(), r.max_abs, r.latency.median, r.latency.p90, r.latency.min);
    s += line;
  }
  return s;
}

nlohmann::json json_of(const SweepFlags& f, const std::vector<Row>& rows, double load_before,
                       double load_after) {
  nlohmann::json j;
  j["load_average_1min"] = {{"start", load_before}, {"end", load_after}};
  j["timing"] = "interleaved blocks: per round, every variant gets 1 untimed + up to " +
                std::to_string(kTimedPerBlock) + " timed inferences";
  j["runs"] = f.runs;
  j["warmup"] = f.warmup;
  j["executor"] = "xnnpack";
  j["error_reference"] = "fp32 model on the reference executor, held-out frames";
  j["calibration"] = {{"data", f.common.calib}, {"frames", f.common.calib_count},
                      {"heldout_frames", f.common.heldout_count}, {"seed", f.common.seed},
                      {"percentile", f.percentile}};
  j["rows"] = nlohmann::json::array();
  for (const Row& r : rows) {
    j["rows"].push_back({{"model", r.model}, {"name", r.model_name}, {"resolution", r.resolution},
                         {"mmac", r.mmac}, {"variant", r.variant}, {"precision", r.precision},
                         {"weights", r.weights}, {"method", r.method},
                         {"bias_correction_frames", r.bias_correction_frames}, {"threads", r.threads},
                         {"int8_ops", r.int8_ops}, {"fp32_ops", r.fp32_ops}, {"bytes", r.bytes},
                         {"cosine_mean", r.cos_mean}, {"cosine_min", r.cos_min},
                         {"sqnr_db", json_number(r.sqnr_db)}, {"max_abs", r.max_abs},
                         {"latency_median_ms", r.latency.median}, {"latency_p90_ms", r.latency.p90},
                         {"latency_min_ms", r.latency.min}});
  }
  return j;
}

std::string svg_of(const SweepFlags& f, const std::vector<Variant>& vars, const std::vector<Row>& rows) {
  PlotSpec spec;
  spec.title = "Embedding error against run time (XNNPACK, median of " + std::to_string(f.runs) + " runs)";
  spec.x_label = "latency per frame, ms (median)";
  spec.y_label = "1 - cosine(embedding, fp32 reference), held-out mean";
  for (const Variant& v : vars) spec.series.push_back(v.name);
  for (const std::string& m : f.models) {
    const std::string name = fs::path(m).filename().string();
    spec.shapes.push_back(name.size() > 34 ? name.substr(0, 31) + "..." : name);
  }
  for (int t : f.threads) spec.fills.push_back(std::to_string(t) + (t == 1 ? " thread" : " threads"));
  // Floor one decade below the smallest int8 error, so fp32 (~0 error) sits just under them.
  double smallest = 1;
  for (const Row& r : rows)
    if (r.precision == "int8" && 1.0 - r.cos_mean > 0) smallest = std::min(smallest, 1.0 - r.cos_mean);
  spec.y_floor = std::pow(10.0, std::floor(std::log10(smallest)) - 1);
  // A log latency axis when the spread is wide (resolutions, or a loaded machine's outliers).
  double fastest = 0, slowest = 0;
  for (const Row& r : rows) {
    fastest = fastest == 0 ? r.latency.median : std::min(fastest, r.latency.median);
    slowest = std::max(slowest, r.latency.median);
  }
  spec.log_x = fastest > 0 && slowest / fastest > 20;
  std::vector<PlotPoint> points;
  for (const Row& r : rows) {
    const size_t fill = static_cast<size_t>(std::find(f.threads.begin(), f.threads.end(), r.threads) - f.threads.begin());
    points.push_back({r.latency.median, std::max(0.0, 1.0 - r.cos_mean), r.variant_index, r.model_index, fill});
  }
  return error_latency_svg(points, spec);
}

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

Status write_text(const fs::path& path, const std::string& text) {
  return tools::write_file(path.string(), std::as_bytes(std::span<const char>(text.data(), text.size())));
}

int run_sweep(const SweepFlags& f) {
  const char* cmd = "quantize-sweep";
  std::vector<quantize::CalibrationMethod> methods;
  for (const std::string& name : f.methods) {
    auto m = quantize::parse_calibration_method(name);
    if (!m.ok()) return report_error(cmd, m.error());
    methods.push_back(*m);
  }
  if (methods.empty()) return report_error(cmd, Error(ErrorCode::kInvalidArgument, "--methods is empty"));
  const std::vector<Variant> vars = variants(methods, f.keep_float, f.bias_correction_frames > 0);
  const double load_before = load_average();
  std::vector<Row> rows;
  for (size_t i = 0; i < f.models.size(); ++i) {
    if (Status s = sweep_model(f, i, vars, rows); !s.ok()) return report_error(cmd, s.error());
  }
  std::error_code ec;
  fs::create_directories(f.out_dir, ec);
  if (ec) return report_error(cmd, Error::make(ErrorCode::kIo, "cannot create '%s': %s", f.out_dir.c_str(), ec.message().c_str()));
  const fs::path dir(f.out_dir);
  for (const auto& [name, text] : {std::pair<const char*, std::string>{"sweep.csv", csv_of(rows)},
                                   {"sweep.json", json_of(f, rows, load_before, load_average()).dump(2) + "\n"},
                                   {"sweep.svg", svg_of(f, vars, rows)}}) {
    if (Status s = write_text(dir / name, text); !s.ok()) return report_error(cmd, s.error());
  }
  bool png = false;
  if (std::system("command -v rsvg-convert >/dev/null 2>&1") == 0) {
    const std::string c = "rsvg-convert -o " + shell_quote((dir / "sweep.png").string()) + " " +
                          shell_quote((dir / "sweep.svg").string());
    png = std::system(c.c_str()) == 0;
  }
  // The variant column is as wide as the longest name, so the figures line up.
  int width = 7;
  for (const Row& r : rows) width = std::max(width, static_cast<int>(r.variant.size()));
  std::printf("%-24s %-9s %-*s %3s %9s %9s %8s %10s %10s\n", "model", "res", width, "variant", "thr",
              "cos mean", "cos min", "SQNR dB", "median ms", "p90 ms");
  for (const Row& r : rows) {
    const std::string name = fs::path(r.model).filename().string();
    std::printf("%-24.24s %-9s %-*s %3d %9.5f %9.5f %8s %10.3f %10.3f\n", name.c_str(),
                r.resolution.c_str(), width, r.variant.c_str(), r.threads, r.cos_mean, r.cos_min,
                format_db(r.sqnr_db).c_str(), r.latency.median, r.latency.p90);
  }
  std::printf("load average (1 min) %.2f at the start, %.2f at the end, on %u cores\n", load_before,
              load_average(), std::thread::hardware_concurrency());
  std::printf("wrote %s/sweep.{csv,json,svg}%s\n", f.out_dir.c_str(), png ? " and sweep.png" : " (no rsvg-convert: no PNG)");
  return kExitOk;
}

}  // namespace

void add_quantize_sweep_command(CLI::App& app, int& exit_code) {
  auto f = std::make_shared<SweepFlags>();
  CLI::App* cmd = app.add_subcommand(
      "quantize-sweep",
      "Error against run time: quantize each model with each variant (per-tensor / per-channel "
      "weights, each calibration method), measure the embedding error on held-out frames and "
      "the XNNPACK latency at each thread count; write CSV, JSON and an SVG plot");
  cmd->add_option("--models", f->models, "Float models (.tlvm), comma-separated (sizes / resolutions)")
      ->required()
      ->delimiter(',')
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", f->out_dir, "Output directory")->required();
  f->common.add_to(*cmd);
  cmd->add_option("--threads", f->threads, "Thread counts, comma-separated")
      ->delimiter(',')
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option("--methods", f->methods, "Calibration methods (the first is also used for the per-tensor row)")
      ->delimiter(',')
      ->check(CLI::IsMember({"minmax", "ema", "percentile", "entropy", "mse"}))
      ->capture_default_str();
  cmd->add_option("--keep-float", f->keep_float,
                  "Also a mixed-precision row: these operators in fp32 ('first' / 'last' as in "
                  "quantize), calibrated with percentile when --methods has it, else the first method")
      ->delimiter(',');
  cmd->add_option("--percentile", f->percentile, "Percentile of the percentile method")
      ->check(CLI::Range(50.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--bias-correction", f->bias_correction_frames,
                  "Empirical bias correction of every int8 variant on this many calibration frames "
                  "(0 = off; otherwise one more row shows the main method without it)")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  cmd->add_option("--runs", f->runs, "Timed inferences per latency figure")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_option("--warmup", f->warmup, "Untimed inferences before timing")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  cmd->add_flag("--quiet,-q", f->quiet, "Progress as one summary line per phase (never redrawn)");
  cmd->footer(std::string(kExitCodeFooter) +
              "\nExample: tlvlink quantize-sweep --models enc96.tlvm,enc128.tlvm --calib /data/t100k "
              "-o /tmp/sweep --threads 1,2");
  cmd->callback([f, &exit_code] { exit_code = run_sweep(*f); });
}

}  // namespace tlvlink::cli
