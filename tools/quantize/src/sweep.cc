// run_sweep: quantize each model with each variant, measure its error and time it (sweep.h).

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>

#include "tlvlink/inspect/graph_stats.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/format.h"
#include "tlvlink/io/model_file.h"
#include "tlvlink/quantize/bias_correction.h"
#include "tlvlink/quantize/layer_error.h"
#include "tlvlink/quantize/sweep.h"

namespace tlvlink::quantize {
namespace {

namespace fs = std::filesystem;

// One executor per (variant, thread count) of a model, warmed up on the first held-out frame.
Result<std::unique_ptr<Executor>> make_timed(const Model& m, int threads,
                                             const std::vector<float>& frame, int warmup) {
  ExecutorOptions o;
  o.threads = threads;
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Executor> exec, make_xnnpack_executor(m, o));
  std::memcpy(exec->input(0).data(), frame.data(), exec->input(0).size());
  for (size_t i = 1; i < m.graph().inputs.size(); ++i)
    std::memset(exec->input(i).data(), 0, exec->input(i).size());
  TLV_TRY(bench::warm_up(*exec, warmup + 1));  // the first inference + the warm-up
  return exec;
}

// The int8 model of a variant (bias-corrected when it asks), with the row's figures.
Result<std::unique_ptr<Model>> quantize_variant(const Model& fp32, const SweepVariant& v,
                                                const SweepOptions& o,
                                                const CalibrationStats& stats,
                                                const CalibData& data, SweepRow& row) {
  CalibrationOptions c;
  c.method = v.method;
  c.percentile = o.percentile;
  QuantizerOptions qo;
  qo.weights = v.weights;
  qo.keep_float = v.keep_float;
  const std::vector<TensorRange> ranges = select_ranges(stats, c);
  QuantizedModel q;
  if (v.bias_correction) {
    BiasCorrectionOptions bo;
    bo.max_frames = static_cast<size_t>(o.bias_correction_frames);
    TLV_ASSIGN_OR_RETURN(auto corrected, correct_biases(fp32, ranges, qo, data.calibration, bo));
    row.bias_correction_frames = corrected.frames;
    q = std::move(corrected.model);
  } else {
    TLV_ASSIGN_OR_RETURN(q, quantize_model(fp32, ranges, qo));
  }
  const std::vector<std::byte> file = q.builder.finish();
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Model> int8, Model::load(file));
  row.bytes = file.size();
  row.int8_ops = q.int8_ops;
  row.fp32_ops = q.float_ops;
  return int8;
}

Status sweep_model(const SweepOptions& o, size_t index, const std::vector<SweepVariant>& vars,
                   std::vector<SweepRow>& rows) {
  const std::string& path = o.models[index];
  TLV_ASSIGN_OR_RETURN(auto model, tools::load_model(path));
  const Model& fp32 = *model;
  const InputSpec& spec = fp32.metadata().input;
  std::string note;
  if (o.on_note)
    o.on_note(
        tools::appendf(note, "quantize-sweep: %s (%dx%d)", path.c_str(), spec.height, spec.width));
  CalibDataOptions data_options = o.data;
  data_options.progress = o.progress;
  auto data = load_calib_data(data_options, spec);
  if (!data.ok()) return data.error().with_context("calibration data for %s", path.c_str());
  TLV_ENSURE(!data->heldout.empty(), ErrorCode::kInvalidArgument,
             "the sweep needs held-out frames (--heldout-count > 0 and data with more than the "
             "calibration frames)");
  TLV_ASSIGN_OR_RETURN(auto stats,
                       calibrate_frames(fp32, data->calibration, o.averaging_constant, o.progress));
  TLV_ASSIGN_OR_RETURN(auto reference, embeddings(fp32, data->heldout));
  const double mmac = static_cast<double>(inspect::graph_stats(fp32.graph()).macs) / 1e6;
  // Quantize every variant and measure its error first; then time them all together.
  std::vector<std::unique_ptr<Model>> models;  // keeps the int8 models alive for their executors
  std::vector<std::unique_ptr<Executor>> executors;
  std::vector<bench::TimedExecutor> timed;
  std::vector<size_t> timed_rows;
  const size_t first_row = rows.size();
  for (size_t vi = 0; vi < vars.size(); ++vi) {
    const SweepVariant& v = vars[vi];
    std::unique_ptr<Model> int8;
    SweepRow base;
    base.model = path;
    base.model_name = std::string(fp32.metadata().name);
    base.resolution = std::to_string(spec.height) + "x" + std::to_string(spec.width);
    base.mmac = mmac;
    base.model_index = index;
    base.variant_index = vi;
    base.variant = v.name;
    base.precision = v.fp32 ? "fp32" : "int8";
    base.weights = v.fp32 ? "-" : weight_granularity_name(v.weights);
    base.method = v.fp32 ? "-" : calibration_method_name(v.method);
    base.bytes = fp32.bytes().size();
    base.fp32_ops = fp32.graph().operators.size();
    if (!v.fp32) {
      TLV_ASSIGN_OR_RETURN(int8, quantize_variant(fp32, v, o, stats, *data, base));
    }
    const Model& m = v.fp32 ? fp32 : *int8;
    // The deployed path: XNNPACK outputs against the fp32 reference executor.
    TLV_ASSIGN_OR_RETURN(auto out, embeddings(m, data->heldout, ExecutorKind::kXnnpack, 1));
    const ModelError e = compare_embeddings(reference, out);
    base.cos_mean = e.mean_cosine();
    base.cos_min = e.min_cosine();
    base.sqnr_db = e.embedding.sqnr_db();
    base.max_abs = e.embedding.max_abs;
    for (int t : o.threads) {
      SweepRow r = base;
      r.threads = t;
      TLV_ASSIGN_OR_RETURN(auto exec, make_timed(m, t, data->heldout.front(), o.warmup));
      executors.push_back(std::move(exec));
      timed_rows.push_back(rows.size());
      rows.push_back(r);
    }
    if (int8) models.push_back(std::move(int8));
  }
  for (const auto& e : executors) timed.push_back({e.get(), {}});
  TLV_TRY(bench::time_interleaved(timed, o.runs));
  for (size_t i = 0; i < timed.size(); ++i)
    rows[timed_rows[i]].latency = bench::latency_stats(timed[i].samples_ms);
  for (size_t i = first_row; i < rows.size() && o.on_note; ++i) {
    note.clear();
    o.on_note(tools::appendf(note, "  %-50s %d thread(s): cosine %.5f, median %.3f ms",
                             rows[i].variant.c_str(), rows[i].threads, rows[i].cos_mean,
                             rows[i].latency.median));
  }
  return {};
}

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

Status write_text(const fs::path& path, const std::string& text) {
  return tools::write_file(path.string(),
                           std::as_bytes(std::span<const char>(text.data(), text.size())));
}

}  // namespace

std::vector<SweepVariant> sweep_variants(const std::vector<CalibrationMethod>& methods,
                                         const std::vector<std::string>& keep_float,
                                         bool bias_correction) {
  std::vector<SweepVariant> v;
  if (methods.empty()) return v;
  v.push_back({"fp32", true, {}, {}, {}});
  // What bias correction does on its own: the main method's per-channel row without it.
  CalibrationMethod main = methods.front();
  for (CalibrationMethod c : methods)
    if (c == CalibrationMethod::kPercentile) main = c;
  if (bias_correction) {
    v.push_back({std::string("int8 per-channel ") + calibration_method_name(main) +
                     " without bias correction",
                 false,
                 WeightGranularity::kPerChannel,
                 main,
                 {},
                 false});
  }
  v.push_back({std::string("int8 per-tensor ") + calibration_method_name(methods.front()),
               false,
               WeightGranularity::kPerTensor,
               methods.front(),
               {}});
  for (CalibrationMethod m : methods)
    v.push_back({std::string("int8 per-channel ") + calibration_method_name(m),
                 false,
                 WeightGranularity::kPerChannel,
                 m,
                 {}});
  if (!keep_float.empty()) {
    std::string list;
    for (const std::string& k : keep_float) list += (list.empty() ? "" : ",") + k;
    // Percentile (quantize's default) when swept, else the first method.
    v.push_back(
        {std::string("int8 per-channel ") + calibration_method_name(main) + " + fp32 " + list,
         false, WeightGranularity::kPerChannel, main, keep_float});
  }
  for (SweepVariant& x : v) x.bias_correction = x.bias_correction && bias_correction && !x.fp32;
  return v;
}

Result<SweepResult> run_sweep(const SweepOptions& o) {
  TLV_ENSURE(!o.methods.empty(), ErrorCode::kInvalidArgument, "--methods is empty");
  TLV_ENSURE(!o.models.empty(), ErrorCode::kInvalidArgument, "no model to sweep");
  SweepResult r;
  r.variants = sweep_variants(o.methods, o.keep_float, o.bias_correction_frames > 0);
  r.load_before = bench::load_average_1min();
  for (size_t i = 0; i < o.models.size(); ++i) TLV_TRY(sweep_model(o, i, r.variants, r.rows));
  r.load_after = bench::load_average_1min();
  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  TLV_ENSURE(!ec, ErrorCode::kIo, "cannot create '%s': %s", o.out_dir.c_str(),
             ec.message().c_str());
  const fs::path dir(o.out_dir);
  TLV_TRY(write_text(dir / "sweep.csv", sweep_csv(r)));
  TLV_TRY(write_text(dir / "sweep.json", sweep_json(o, r).dump(2) + "\n"));
  TLV_TRY(write_text(dir / "sweep.svg", sweep_svg(o, r)));
  if (std::system("command -v rsvg-convert >/dev/null 2>&1") == 0) {
    const std::string c = "rsvg-convert -o " + shell_quote((dir / "sweep.png").string()) + " " +
                          shell_quote((dir / "sweep.svg").string());
    r.png = std::system(c.c_str()) == 0;
  }
  return r;
}

}  // namespace tlvlink::quantize
