// tlvlink quantize FLOAT.tlvm --calib DATA -o INT8.tlvm: calibration on real or simulated
// frames (through the deployment preprocessing), int8 conversion with mixed-precision fallback,
// golden pairs, and the per-layer / end-to-end error report on held-out frames.

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <optional>
#include <sstream>

#include "cli/common.h"
#include "cli/quantize_data.h"
#include "cli/quantize_eval.h"
#include "cli/quantize_options.h"
#include "cli/quantize_report.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/progress.h"
#include "tlvlink/quantize/bias_correction.h"
#include "tlvlink/quantize/layer_error.h"
#include "tlvlink/quantize/quantizer.h"

namespace tlvlink::cli {
namespace {

using quantize::MetadataSpec;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct QuantizeFlags {
  std::string model, output, report_dir;
  QuantizeCommonFlags common;
  std::string method = "percentile";
  double percentile = 99.99;
  std::string weights = "per-channel";
  std::vector<std::string> keep_float;
  double max_bias_raise = 16.0;
  bool no_fuse = false;
  int golden = 2;
  int bias_correction_frames = 64;
  TaskEvalFlags tasks;
  bool quiet = false;
};

Status check_keep_float(const Model& m, const std::vector<std::string>& names) {
  for (const std::string& n : names) {
    if (n == "first" || n == "last") continue;
    bool found = false;
    for (const Operator& op : m.graph().operators) found = found || op.name == n;
    TLV_ENSURE(found, ErrorCode::kInvalidArgument,
               "--keep-float '%s': the model has no operator of that name (see tlvlink inspect)",
               n.c_str());
  }
  return {};
}

// "encoder-fp32" -> "encoder-int8"; "encoder" -> "encoder-int8"; "x-int8" stays.
std::string int8_name(const std::string& name) {
  const auto ends = [&](const char* s) {
    const std::string x(s);
    return name.size() >= x.size() && name.compare(name.size() - x.size(), x.size(), x) == 0;
  };
  if (ends("-int8")) return name;
  if (ends("-fp32")) return name.substr(0, name.size() - 5) + "-int8";
  return name.empty() ? "int8" : name + "-int8";
}

Status add_golden(quantize::ModelBuilder& b, const std::vector<std::vector<float>>& frames,
                  int count) {
  const std::vector<std::byte> file = b.finish();
  TLV_ASSIGN_OR_RETURN(auto model, Model::load(file));
  for (int i = 0; i < count && static_cast<size_t>(i) < frames.size(); ++i) {
    const std::span<const std::byte> in = std::as_bytes(std::span<const float>(frames[static_cast<size_t>(i)]));
    TLV_ASSIGN_OR_RETURN(std::vector<std::byte> out, quantize::run_reference(*model, in));
    b.metadata().golden.emplace_back(std::vector<std::byte>(in.begin(), in.end()), std::move(out));
  }
  return {};
}

std::string quantization_json(const QuantizeFlags& f, const quantize::CalibrationOptions& c,
                              const CalibData& data, const std::string& fallbacks,
                              const Provenance& source) {
  nlohmann::ordered_json j = {
      {"kind", "post-training"},
      {"tool", "tlvlink quantize"},
      {"source", {{"model", f.model},
                  {"producer", std::string(source.producer)},
                  {"created_utc", std::string(source.created_utc)},
                  {"content_checksum", source.content_checksum}}},
      {"method", quantize::calibration_method_name(c.method)},
      {"percentile", c.percentile},
      {"calibration", calib_format_name(data.format)},
      {"frames", data.calibration.size()},
      {"seed", f.common.seed},
      {"activations", "int8 per-tensor asymmetric"},
      {"weights", "int8 " + f.weights + " symmetric [-127,127]"},
      {"bias", "int32"},
      {"bias_correction_frames", f.bias_correction_frames},
      {"fp32_layers", fallbacks}};
  return j.dump();
}

int run_quantize(const QuantizeFlags& f) {
  const char* cmd = "quantize";
  QuantizeRun run;
  run.input_path = f.model;
  run.output_path = f.output;
  auto t0 = Clock::now();
  auto model = load_model(f.model);
  if (!model.ok()) return report_error(cmd, model.error());
  const Model& fp32 = **model;
  quantize::CalibrationOptions copt;
  auto method = quantize::parse_calibration_method(f.method);
  if (!method.ok()) return report_error(cmd, method.error());
  copt.method = *method;
  copt.percentile = f.percentile;
  if (Status s = quantize::validate(copt); !s.ok()) return report_error(cmd, s.error());
  if (Status s = check_keep_float(fp32, f.keep_float); !s.ok()) return report_error(cmd, s.error());
  run.timing.emplace_back("load", seconds_since(t0));

  t0 = Clock::now();
  auto data = load_calib_data(f.common.data_options(!f.quiet), fp32.metadata().input);
  if (!data.ok()) return report_error(cmd, data.error().with_context("calibration data"));
  run.data_summary = data->summary;
  run.timing.emplace_back("read frames", seconds_since(t0));

  t0 = Clock::now();
  auto stats = calibrate_with_progress(fp32, data->calibration, f.common, !f.quiet);
  if (!stats.ok()) return report_error(cmd, stats.error());
  run.timing.emplace_back("calibrate", seconds_since(t0));

  t0 = Clock::now();
  quantize::QuantizerOptions qopt;
  qopt.weights = f.weights == "per-tensor" ? quantize::WeightGranularity::kPerTensor
                                           : quantize::WeightGranularity::kPerChannel;
  qopt.keep_float = f.keep_float;
  qopt.max_bias_scale_raise = f.max_bias_raise;
  qopt.fuse_clamps = !f.no_fuse;
  const std::vector<quantize::TensorRange> ranges = quantize::select_ranges(*stats, copt);
  std::optional<quantize::CorrectedModel> corrected;
  auto make_int8 = [&]() -> Result<quantize::QuantizedModel> {
    if (f.bias_correction_frames <= 0) return quantize::quantize_model(fp32, ranges, qopt);
    const auto layers = static_cast<int64_t>(quantize::correctable_layers(fp32.graph()));
    tools::Progress p("quantize: bias correction (layers)", layers, stderr,
                      f.quiet ? tools::ProgressMode::kQuiet : tools::ProgressMode::kAuto);
    quantize::BiasCorrectionOptions bo;
    bo.max_frames = static_cast<size_t>(f.bias_correction_frames);
    bo.on_layer = [&p](size_t done, size_t) { p.set(static_cast<int64_t>(done)); };
    auto c = quantize::correct_biases(fp32, ranges, qopt, data->calibration, bo);
    p.finish();
    if (!c.ok()) return c.error();
    corrected = std::move(c).value();
    return std::move(corrected->model);
  };
  auto q = make_int8();
  if (!q.ok()) return report_error(cmd, q.error());
  std::string fallbacks;
  for (const quantize::LayerDecision& d : q->layers)
    if (d.precision == quantize::LayerPrecision::kFloat && d.fused_into.empty())
      fallbacks += (fallbacks.empty() ? "" : "; ") + d.op + ": " + d.reason;
  // Provenance: this tool made the file now; the float model it came from is in `quantization`.
  MetadataSpec& meta = q->builder.metadata();
  meta.quantization_json = quantization_json(f, copt, *data, fallbacks, fp32.metadata().provenance);
  meta.name = int8_name(meta.name);
  meta.producer = "tlvlink quantize";
  meta.created_utc.clear();
  if (Status s = add_golden(q->builder, data->heldout, f.golden); !s.ok())
    return report_error(cmd, s.error().with_context("golden pairs"));
  const std::vector<std::byte> file = q->builder.finish();
  auto int8 = Model::load(file);
  if (!int8.ok()) return report_error(cmd, int8.error().with_context("quantized model (quantizer bug)"));
  // The deployed path must accept it: create (not run) the XNNPACK executor once.
  if (auto x = make_xnnpack_executor(**int8); !x.ok() && x.error().code() != ErrorCode::kModelUnsupported)
    return report_error(cmd, x.error().with_context("XNNPACK rejects the quantized model (quantizer bug)"));
  if (Status s = tools::write_file(f.output, file); !s.ok()) return report_error(cmd, s.error());
  run.timing.emplace_back("quantize", seconds_since(t0));
  run.output_bytes = file.size();
  run.golden_pairs = (*int8)->metadata().golden.size();

  t0 = Clock::now();
  std::optional<quantize::ModelError> error;
  if (!data->heldout.empty()) {
    tools::Progress p("quantize: error report", static_cast<int64_t>(data->heldout.size()), stderr,
                      f.quiet ? tools::ProgressMode::kQuiet : tools::ProgressMode::kAuto);
    quantize::CompareOptions co;
    co.on_frame = [&p](uint64_t done) { p.set(static_cast<int64_t>(done)); };
    auto e = quantize::compare_models(fp32, **int8, data->heldout, co);
    p.finish();
    if (!e.ok()) return report_error(cmd, e.error().with_context("error report"));
    error = std::move(e).value();
    run.timing.emplace_back("error report", seconds_since(t0));
  }
  if (f.tasks.requested()) {
    t0 = Clock::now();
    auto tasks = compare_tasks(fp32, **int8, f.tasks);
    if (!tasks.ok()) return report_error(cmd, tasks.error().with_context("task accuracies"));
    char drop[160];
    std::snprintf(drop, sizeof(drop),
                  "  largest accuracy drop fp32 -> int8 over the available cells: %.1f points\n",
                  tasks->max_drop_points);
    run.tasks_table = tasks->table + drop;
    run.tasks_json = tasks->json;
    run.timing.emplace_back("tasks", seconds_since(t0));
  } else {
    run.tasks_note = "not measured (give --eval-touch / --eval-grasp)";
  }
  run.calibration = copt;
  run.averaging_constant = f.common.averaging_constant;
  run.weights = qopt.weights;
  run.keep_float = f.keep_float;
  run.calibration_frames = stats->frames;
  run.heldout_frames = data->heldout.size();
  run.quantized = &*q;
  run.corrected = corrected ? &*corrected : nullptr;
  run.error = error ? &*error : nullptr;
  if (!f.report_dir.empty()) {
    if (Status s = write_report(f.report_dir, run); !s.ok()) return report_error(cmd, s.error());
  }
  std::fputs(format_summary(run).c_str(), stdout);
  if (!f.report_dir.empty()) std::printf("  %-12s %s/{report.json,layers.csv,summary.txt}\n", "report", f.report_dir.c_str());
  return kExitOk;
}

}  // namespace

void add_quantize_command(CLI::App& app, int& exit_code) {
  auto f = std::make_shared<QuantizeFlags>();
  CLI::App* cmd = app.add_subcommand(
      "quantize",
      "Quantize a float model to int8: calibrate on frames (dataset, image folder or the "
      "simulator's extreme set) through the model's own preprocessing, keep layers that cannot "
      "meet int8 constraints in fp32, and report the per-layer and end-to-end error on "
      "held-out frames");
  cmd->add_option("model", f->model, "Float model (.tlvm), e.g. from gen-reference --dtype fp32, "
                                     "convert or the trainer's export")
      ->required();
  cmd->add_option("-o,--output", f->output, "Output int8 model (.tlvm)")->required();
  f->common.add_to(*cmd);
  cmd->add_option("--method,-m", f->method,
                  "Calibration method: minmax, ema (moving-average minmax), percentile, entropy "
                  "(KL, TensorRT-style), mse")
      ->check(CLI::IsMember({"minmax", "ema", "percentile", "entropy", "mse"}))
      ->capture_default_str();
  cmd->add_option("--percentile", f->percentile, "Percentile for --method percentile, in (50, 100]")
      ->check(CLI::Range(50.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--weights", f->weights, "Weight scales: per-channel or per-tensor")
      ->check(CLI::IsMember({"per-channel", "per-tensor"}))
      ->capture_default_str();
  cmd->add_option("--keep-float", f->keep_float,
                  "Operator(s) to keep in fp32 (repeat or comma-separate); 'first' / 'last' name "
                  "the first / last conv or fully-connected layer")
      ->delimiter(',');
  cmd->add_option("--max-bias-raise", f->max_bias_raise,
                  "Largest factor a weight scale may be raised by so an int32 bias fits; beyond "
                  "it the layer stays fp32")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  cmd->add_flag("--no-fuse", f->no_fuse, "Do not fuse standalone ReLU/ReLU6 clamps into the op before");
  cmd->add_option("--bias-correction", f->bias_correction_frames,
                  "Empirical bias correction on this many calibration frames (0 = off): each "
                  "conv/FC layer's mean output shift per channel, caused by quantization, is "
                  "measured and removed from its bias, layer by layer")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  cmd->add_option("--golden", f->golden, "Golden I/O pairs to embed (from held-out frames)")
      ->check(CLI::Range(0, 8))
      ->capture_default_str();
  cmd->add_option("--report", f->report_dir, "Write report.json, layers.csv and summary.txt here");
  cmd->add_option("--eval-touch", f->tasks.touch_dir,
                  "Touch100k / Touch-and-Go dir: also report fp32 vs int8 task accuracies");
  cmd->add_option("--eval-grasp", f->tasks.grasp_dir,
                  "Feel dir (or .h5): also report fp32 vs int8 grasp accuracy");
  cmd->add_flag("--quiet,-q", f->quiet, "Progress as one summary line per phase (never redrawn)");
  cmd->footer(std::string(kExitCodeFooter) +
              "\nExample: tlvlink quantize encoder.tlvm --calib /data/t100k -o encoder_int8.tlvm "
              "--method percentile --report /tmp/qreport");
  cmd->callback([f, &exit_code] { exit_code = run_quantize(*f); });
}

}  // namespace tlvlink::cli
