// Terminal summary and report files of `tlvlink quantize`.

#include "tlvlink/quantize/report.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "tlvlink/io/file.h"

namespace tlvlink::quantize {
namespace {

const char* precision_name(quantize::LayerPrecision p) {
  return p == quantize::LayerPrecision::kInt8 ? "int8" : "fp32";
}

// Fixed ("%.*f") or general ("%.*g") notation; "inf" / "-" for non-finite values.
std::string fmt(double v, int precision, bool general = false) {
  if (!std::isfinite(v)) return v > 0 ? "inf" : "-";
  char text[64];
  if (general) {
    std::snprintf(text, sizeof(text), "%.*g", precision, v);
  } else {
    std::snprintf(text, sizeof(text), "%.*f", precision, v);
  }
  return text;
}

std::map<std::string, const quantize::TensorError*> errors_by_op(const QuantizeRun& run) {
  std::map<std::string, const quantize::TensorError*> m;
  if (run.error)
    for (const quantize::TensorError& e : run.error->layers) m[e.op] = &e;
  return m;
}

std::string method_text(const QuantizeRun& run) {
  std::string m = quantize::calibration_method_name(run.calibration.method);
  char extra[64] = "";
  if (run.calibration.method == quantize::CalibrationMethod::kPercentile)
    std::snprintf(extra, sizeof(extra), " %g", run.calibration.percentile);
  if (run.calibration.method == quantize::CalibrationMethod::kEma)
    std::snprintf(extra, sizeof(extra), " (averaging constant %g)", run.averaging_constant);
  return m + extra;
}

}  // namespace

std::string format_db(double db) { return fmt(db, 1); }

nlohmann::json json_number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

std::string csv_cell(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string format_summary(const QuantizeRun& run) {
  const quantize::QuantizedModel& q = run.quantized;
  std::string s;
  char line[512];
  // One labelled entry; a text of several lines (one per calibration source) continues under
  // the first, aligned.
  auto add = [&](const char* label, const std::string& text) {
    std::snprintf(line, sizeof(line), "  %-12s ", label);
    std::string entry = line;
    const std::string continuation = "\n" + std::string(entry.size(), ' ');
    for (char c : text) entry += c == '\n' ? continuation : std::string(1, c);
    s += entry + "\n";
  };
  s += "tlvlink quantize: " + run.input_path + " -> " + run.output_path + "\n";
  add("data", run.data_summary);
  add("method", method_text(run) + "; weights int8 " +
                    quantize::weight_granularity_name(run.weights) +
                    " symmetric [-127,127]; activations int8 per-tensor asymmetric; bias int32");
  std::snprintf(
      line, sizeof(line),
      "%zu int8, %zu fp32, %zu fused into the op before; %zu Quantize/Dequantize inserted",
      q.int8_ops, q.float_ops, q.fused_ops, q.conversions);
  add("operators", line);
  bool first = true;
  for (const quantize::LayerDecision& d : q.layers) {
    if (d.precision != quantize::LayerPrecision::kFloat || !d.fused_into.empty()) continue;
    add(first ? "fp32 layers" : "", d.op + " (" + op_type_name(d.type) + "): " + d.reason);
    first = false;
  }
  if (run.corrected) {
    const quantize::CorrectedModel& c = *run.corrected;
    double worst = 0;
    std::string worst_op;
    for (const quantize::BiasCorrectionLayer& l : c.layers) {
      const double in_steps = l.int8 && l.step > 0 ? l.max_abs_shift / l.step : 0;
      if (in_steps >= worst) worst = in_steps, worst_op = l.op;
    }
    std::snprintf(line, sizeof(line),
                  "%zu layers on %zu calibration frames; largest mean shift removed %.2f int8 "
                  "steps (%s)",
                  c.layers.size(), c.frames, worst, worst_op.c_str());
    add("bias corr.", line);
  } else {
    add("bias corr.", "off");
  }
  first = true;
  for (const quantize::LayerDecision& d : q.layers) {
    for (const std::string& a : d.adjustments) {
      add(first ? "adjustments" : "", d.op + ": " + a);
      first = false;
    }
  }
  if (run.error && run.error->frames > 0) {
    const quantize::ModelError& e = *run.error;
    std::snprintf(line, sizeof(line),
                  "cosine vs fp32 on %llu held-out frames: mean %.5f, min %.5f; SQNR %s dB, "
                  "max |err| %.4g",
                  static_cast<unsigned long long>(e.frames), e.mean_cosine(), e.min_cosine(),
                  format_db(e.embedding.sqnr_db()).c_str(), e.embedding.max_abs);
    add("embedding", line);
    s += "\n  per layer (fp32 reference executor vs quantized, accumulated through the network):\n";
    std::snprintf(line, sizeof(line), "  %-28s %-17s %-5s %8s %9s %10s %10s %8s\n", "layer", "type",
                  "dtype", "SQNR dB", "cosine", "max-abs", "RMSE/step", "w-SQNR");
    s += line;
    const auto errors = errors_by_op(run);
    for (const quantize::LayerDecision& d : q.layers) {
      const auto it = errors.find(d.op);
      if (it == errors.end()) continue;
      const quantize::TensorError& t = *it->second;
      std::snprintf(line, sizeof(line), "  %-28.28s %-17s %-5s %8s %9.5f %10.4g %10s %8s\n",
                    d.op.c_str(), op_type_name(d.type), t.dtype == DType::kInt8 ? "int8" : "fp32",
                    format_db(t.error.sqnr_db()).c_str(), t.error.cosine(), t.error.max_abs,
                    t.scale > 0 ? fmt(t.rmse_over_scale(), 3).c_str() : "-",
                    format_db(d.weight_sqnr_db).c_str());
      s += line;
    }
    s += "  (RMSE/step ~0.29 is plain rounding; w-SQNR is the weights alone)\n\n";
  } else {
    add("error", "not measured (no held-out frames)");
  }
  if (!run.tasks_table.empty()) s += "  task accuracy, fp32 vs int8:\n" + run.tasks_table + "\n";
  if (!run.tasks_note.empty()) add("tasks", run.tasks_note);
  std::string t;
  double total = 0;
  for (const auto& [phase, seconds] : run.timing) {
    std::snprintf(line, sizeof(line), "%s%s %.1f s", t.empty() ? "" : ", ", phase.c_str(), seconds);
    t += line;
    total += seconds;
  }
  std::snprintf(line, sizeof(line), "; total %.1f s", total);
  add("time", t + line);
  std::snprintf(line, sizeof(line), "%s (%zu bytes, %zu golden pairs from held-out frames%s)",
                run.output_path.c_str(), run.output_bytes, run.golden_pairs,
                run.golden_skipped > 0
                    ? (", " + std::to_string(run.golden_skipped) +
                       " skipped: the executors round a half-way case apart on them")
                          .c_str()
                    : "");
  add("wrote", line);
  return s;
}

nlohmann::json report_json(const QuantizeRun& run) {
  const quantize::QuantizedModel& q = run.quantized;
  nlohmann::ordered_json j;
  const auto errors = errors_by_op(run);
  nlohmann::ordered_json layers = nlohmann::ordered_json::array();
  for (const quantize::LayerDecision& d : q.layers) {
    nlohmann::ordered_json l = {{"op", d.op},
                                {"type", op_type_name(d.type)},
                                {"precision", precision_name(d.precision)},
                                {"reason", d.reason},
                                {"adjustments", d.adjustments},
                                {"fused_into", d.fused_into},
                                {"weight_sqnr_db", json_number(d.weight_sqnr_db)}};
    if (const auto it = errors.find(d.op); it != errors.end()) {
      const quantize::TensorError& t = *it->second;
      l["tensor"] = t.tensor;
      l["dtype"] = dtype_name(t.dtype);
      l["scale"] = t.scale;
      l["sqnr_db"] = json_number(t.error.sqnr_db());
      l["cosine"] = json_number(t.error.cosine());
      l["max_abs"] = t.error.max_abs;
      l["rmse"] = t.error.rmse();
      l["rmse_over_scale"] =
          t.scale > 0 ? json_number(t.rmse_over_scale()) : nlohmann::json(nullptr);
    }
    layers.push_back(l);
  }
  j["input_model"] = run.input_path;
  j["output_model"] = run.output_path;
  j["output_bytes"] = run.output_bytes;
  j["calibration"] = {{"data", run.data_summary},
                      {"method", quantize::calibration_method_name(run.calibration.method)},
                      {"percentile", run.calibration.percentile},
                      {"averaging_constant", run.averaging_constant},
                      {"frames", run.calibration_frames},
                      {"heldout_frames", run.heldout_frames}};
  j["weights"] = quantize::weight_granularity_name(run.weights);
  if (run.corrected) {
    nlohmann::json bc = nlohmann::json::array();
    for (const quantize::BiasCorrectionLayer& l : run.corrected->layers) {
      bc.push_back({{"op", l.op},
                    {"dtype", l.int8 ? "int8" : "fp32"},
                    {"step", l.step},
                    {"mean_abs_shift", l.mean_abs_shift},
                    {"max_abs_shift", l.max_abs_shift},
                    {"channels", l.channels},
                    {"channels_measured", l.channels_measured}});
    }
    j["bias_correction"] = {{"frames", run.corrected->frames}, {"layers", bc}};
  } else {
    j["bias_correction"] = nullptr;
  }
  j["keep_float"] = run.keep_float;
  j["operators"] = {{"int8", q.int8_ops},
                    {"fp32", q.float_ops},
                    {"fused", q.fused_ops},
                    {"conversions_inserted", q.conversions}};
  if (run.error) {
    const quantize::ModelError& e = *run.error;
    j["embedding"] = {{"frames", e.frames},
                      {"cosine_mean", json_number(e.mean_cosine())},
                      {"cosine_min", json_number(e.min_cosine())},
                      {"sqnr_db", json_number(e.embedding.sqnr_db())},
                      {"max_abs", e.embedding.max_abs},
                      {"rmse", e.embedding.rmse()},
                      {"frame_cosine", e.frame_cosine}};
  }
  j["layers"] = layers;
  if (!run.tasks_json.is_null()) j["tasks"] = run.tasks_json;
  if (!run.tasks_note.empty()) j["tasks_note"] = run.tasks_note;
  nlohmann::ordered_json timing;
  for (const auto& [phase, seconds] : run.timing) timing[phase] = seconds;
  j["timing_s"] = timing;
  return j;
}

Status write_report(const std::string& dir, const QuantizeRun& run) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  TLV_ENSURE(!ec, ErrorCode::kIo, "cannot create report directory '%s': %s", dir.c_str(),
             ec.message().c_str());
  const std::filesystem::path out_dir(dir);
  auto write = [&](const char* name, const std::string& text) {
    return tools::write_file(
        (out_dir / name).string(),
        std::span<const std::byte>(reinterpret_cast<const std::byte*>(text.data()), text.size()));
  };
  TLV_TRY(write("report.json", report_json(run).dump(2) + "\n"));
  TLV_TRY(write("summary.txt", format_summary(run)));
  std::string csv =
      "op,type,precision,dtype,sqnr_db,cosine,max_abs,rmse_over_scale,weight_sqnr_db,reason,"
      "adjustments\n";
  const auto errors = errors_by_op(run);
  for (const quantize::LayerDecision& d : run.quantized.layers) {
    const auto it = errors.find(d.op);
    const quantize::TensorError* t = it == errors.end() ? nullptr : it->second;
    std::string adjustments;
    for (const std::string& a : d.adjustments) adjustments += (adjustments.empty() ? "" : "; ") + a;
    csv += csv_cell(d.op) + "," + op_type_name(d.type) + "," + precision_name(d.precision) + "," +
           (t ? dtype_name(t->dtype) : "") + "," + (t ? fmt(t->error.sqnr_db(), 3) : "") + "," +
           (t ? fmt(t->error.cosine(), 6) : "") + "," + (t ? fmt(t->error.max_abs, 6, true) : "") +
           "," + (t && t->scale > 0 ? fmt(t->rmse_over_scale(), 4) : "") + "," +
           fmt(d.weight_sqnr_db, 3) + "," +
           csv_cell(d.fused_into.empty() ? d.reason : "fused into " + d.fused_into) + "," +
           csv_cell(adjustments) + "\n";
  }
  return write("layers.csv", csv);
}

}  // namespace tlvlink::quantize
