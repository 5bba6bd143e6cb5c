// run_quantize: `tlvlink quantize` as a library call (pipeline.h).

#include "tlvlink/quantize/pipeline.h"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "tlvlink/executor.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/model_file.h"
#include "tlvlink/io/progress.h"
#include "tlvlink/quantize/bias_correction.h"
#include "tlvlink/quantize/calibrate.h"
#include "tlvlink/quantize/layer_error.h"
#include "tlvlink/verify/compare.h"

namespace tlvlink::quantize {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

tools::ProgressMode progress_mode(bool progress) {
  return progress ? tools::ProgressMode::kAuto : tools::ProgressMode::kQuiet;
}

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

// Golden pairs are checked on the board by its own executor (XNNPACK) against outputs computed
// here by the reference executor. On a frame where an int8 activation lands exactly half-way
// between two levels the two executors may round it apart by one step (verify/compare.h), and a
// float layer after the int8 part magnifies that step past the float rule: such a frame would
// fail every board's self-test. So a held-out frame becomes a golden pair only when every
// executor built here reproduces the reference under verify's rules; the skipped ones are
// counted.
Result<int> add_golden(ModelBuilder& b, const std::vector<std::vector<float>>& frames, int count) {
  const std::vector<std::byte> file = b.finish();
  TLV_ASSIGN_OR_RETURN(auto model, Model::load(file));
  std::unique_ptr<Executor> xnnpack;
  if (auto x = make_executor(*model, ExecutorKind::kXnnpack, {}); x.ok()) xnnpack = std::move(*x);
  int added = 0, skipped = 0;
  for (size_t i = 0; i < frames.size() && added < count; ++i) {
    const std::span<const std::byte> in = std::as_bytes(std::span<const float>(frames[i]));
    TLV_ASSIGN_OR_RETURN(std::vector<std::byte> out, run_reference(*model, in));
    if (xnnpack) {
      std::span<std::byte> dst = xnnpack->input(0);
      TLV_ENSURE(dst.size() == in.size(), ErrorCode::kShapeMismatch,
                 "golden frame of %zu bytes, model input %zu", in.size(), dst.size());
      std::memcpy(dst.data(), in.data(), in.size());
      TLV_TRY(xnnpack->invoke());
      const int32_t output = model->graph().outputs[0];
      const verify::OutputComparison c =
          verify::compare_output_bytes(model->graph(), output, xnnpack->output(0), out);
      if (!c.pass) {
        ++skipped;
        continue;
      }
    }
    b.metadata().golden.emplace_back(std::vector<std::byte>(in.begin(), in.end()), std::move(out));
    ++added;
  }
  return skipped;
}

std::string quantization_json(const QuantizeOptions& o, const CalibData& data,
                              const std::string& fallbacks, const Provenance& source) {
  nlohmann::ordered_json j = {
      {"kind", "post-training"},
      {"tool", "tlvlink quantize"},
      {"source",
       {{"model", o.model_path},
        {"producer", std::string(source.producer)},
        {"created_utc", std::string(source.created_utc)},
        {"content_checksum", source.content_checksum}}},
      {"method", calibration_method_name(o.calibration.method)},
      {"percentile", o.calibration.percentile},
      {"calibration", calib_formats_name(data.formats)},
      {"frames", data.calibration.size()},
      {"seed", o.data.seed},
      {"activations", "int8 per-tensor asymmetric"},
      {"weights", std::string("int8 ") + weight_granularity_name(o.quantizer.weights) +
                      " symmetric [-127,127]"},
      {"bias", "int32"},
      {"bias_correction_frames", o.bias_correction_frames},
      {"fp32_layers", fallbacks}};
  return j.dump();
}

// The int8 model, bias-corrected layer by layer on the calibration frames when asked.
Result<QuantizedModel> make_int8(const Model& fp32, const std::vector<TensorRange>& ranges,
                                 const QuantizeOptions& o, const CalibData& data,
                                 std::optional<CorrectedModel>& corrected) {
  if (o.bias_correction_frames <= 0) return quantize_model(fp32, ranges, o.quantizer);
  const auto layers = static_cast<int64_t>(correctable_layers(fp32.graph()));
  tools::Progress p("quantize: bias correction (layers)", layers, stderr,
                    progress_mode(o.progress));
  BiasCorrectionOptions bo;
  bo.max_frames = static_cast<size_t>(o.bias_correction_frames);
  bo.on_layer = [&p](size_t done, size_t) { p.set(static_cast<int64_t>(done)); };
  auto c = correct_biases(fp32, ranges, o.quantizer, data.calibration, bo);
  p.finish();
  if (!c.ok()) return c.error();
  corrected = std::move(c).value();
  return std::move(corrected->model);
}

Status measure_tasks(const Model& fp32, const Model& int8, const QuantizeOptions& o,
                     QuantizeRun& run) {
  if (!o.tasks.requested()) {
    run.tasks_note = "not measured (give --eval-touch / --eval-grasp)";
    return {};
  }
  const auto t0 = Clock::now();
  auto tasks = compare_tasks(fp32, int8, o.tasks);
  if (!tasks.ok()) return tasks.error().with_context("task accuracies");
  char drop[160];
  std::snprintf(drop, sizeof(drop),
                "  largest accuracy drop fp32 -> int8 over the available cells: %.1f points\n",
                tasks->max_drop_points);
  run.tasks_table = tasks->table + drop;
  run.tasks_json = tasks->json;
  run.timing.emplace_back("tasks", seconds_since(t0));
  return {};
}

}  // namespace

std::string int8_model_name(const std::string& name) {
  const auto ends = [&](const char* s) {
    const std::string x(s);
    return name.size() >= x.size() && name.compare(name.size() - x.size(), x.size(), x) == 0;
  };
  if (ends("-int8")) return name;
  if (ends("-fp32")) return name.substr(0, name.size() - 5) + "-int8";
  return name.empty() ? "int8" : name + "-int8";
}

Result<QuantizeRun> run_quantize(const QuantizeOptions& o) {
  QuantizeRun run;
  run.input_path = o.model_path;
  run.output_path = o.output_path;
  auto t0 = Clock::now();
  TLV_ASSIGN_OR_RETURN(const std::unique_ptr<Model> model, tools::load_model(o.model_path));
  const Model& fp32 = *model;
  TLV_TRY(validate(o.calibration));
  TLV_TRY(check_keep_float(fp32, o.quantizer.keep_float));
  run.timing.emplace_back("load", seconds_since(t0));

  t0 = Clock::now();
  CalibDataOptions data_options = o.data;
  data_options.progress = o.progress;
  auto data = load_calib_data(data_options, fp32.metadata().input);
  if (!data.ok()) return data.error().with_context("calibration data");
  run.data_summary = data->summary;
  run.timing.emplace_back("read frames", seconds_since(t0));

  t0 = Clock::now();
  TLV_ASSIGN_OR_RETURN(const CalibrationStats stats,
                       calibrate_frames(fp32, data->calibration, o.averaging_constant, o.progress));
  run.timing.emplace_back("calibrate", seconds_since(t0));

  t0 = Clock::now();
  const std::vector<TensorRange> ranges = select_ranges(stats, o.calibration);
  TLV_ASSIGN_OR_RETURN(run.quantized, make_int8(fp32, ranges, o, *data, run.corrected));
  QuantizedModel& q = run.quantized;
  std::string fallbacks;
  for (const LayerDecision& d : q.layers)
    if (d.precision == LayerPrecision::kFloat && d.fused_into.empty())
      fallbacks += (fallbacks.empty() ? "" : "; ") + d.op + ": " + d.reason;
  // Provenance: this tool made the file now; the float model it came from is in `quantization`.
  MetadataSpec& meta = q.builder.metadata();
  meta.quantization_json = quantization_json(o, *data, fallbacks, fp32.metadata().provenance);
  meta.name = int8_model_name(meta.name);
  meta.producer = "tlvlink quantize";
  meta.created_utc.clear();
  auto skipped = add_golden(q.builder, data->heldout, o.golden_pairs);
  if (!skipped.ok()) return skipped.error().with_context("golden pairs");
  run.golden_skipped = *skipped;
  const std::vector<std::byte> file = q.builder.finish();
  auto int8 = Model::load(file);
  if (!int8.ok()) return int8.error().with_context("quantized model (quantizer bug)");
  // The deployed path must accept it: create (not run) the XNNPACK executor once.
  if (auto x = make_xnnpack_executor(**int8);
      !x.ok() && x.error().code() != ErrorCode::kModelUnsupported)
    return x.error().with_context("XNNPACK rejects the quantized model (quantizer bug)");
  TLV_TRY(tools::write_file(o.output_path, file));
  run.timing.emplace_back("quantize", seconds_since(t0));
  run.output_bytes = file.size();
  run.golden_pairs = (*int8)->metadata().golden.size();

  t0 = Clock::now();
  if (!data->heldout.empty()) {
    tools::Progress p("quantize: error report", static_cast<int64_t>(data->heldout.size()), stderr,
                      progress_mode(o.progress));
    CompareOptions co;
    co.on_frame = [&p](uint64_t done) { p.set(static_cast<int64_t>(done)); };
    auto e = compare_models(fp32, **int8, data->heldout, co);
    p.finish();
    if (!e.ok()) return e.error().with_context("error report");
    run.error = std::move(e).value();
    run.timing.emplace_back("error report", seconds_since(t0));
  }
  TLV_TRY(measure_tasks(fp32, **int8, o, run));
  run.calibration = o.calibration;
  run.averaging_constant = o.averaging_constant;
  run.weights = o.quantizer.weights;
  run.keep_float = o.quantizer.keep_float;
  run.calibration_frames = stats.frames;
  run.heldout_frames = data->heldout.size();
  if (!o.report_dir.empty()) TLV_TRY(write_report(o.report_dir, run));
  return run;
}

}  // namespace tlvlink::quantize
