#pragma once
// What `tlvlink quantize` tells the user about a run (pipeline.h makes one): a terminal summary
// (decisions, fp32 fallbacks with their reasons, adjustments, per-layer error, embedding cosine,
// timing) and, with a report directory, the same as files: report.json (everything), layers.csv
// (one row per layer), summary.txt.

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tlvlink/error.h"
#include "tlvlink/quantize/bias_correction.h"
#include "tlvlink/quantize/calibration_method.h"
#include "tlvlink/quantize/layer_error.h"
#include "tlvlink/quantize/quantizer.h"

namespace tlvlink::quantize {

struct QuantizeRun {
  std::string input_path, output_path;
  std::string data_summary;
  quantize::CalibrationOptions calibration;
  double averaging_constant = 0;
  quantize::WeightGranularity weights = quantize::WeightGranularity::kPerChannel;
  std::vector<std::string> keep_float;
  uint64_t calibration_frames = 0, heldout_frames = 0;
  QuantizedModel quantized;
  std::optional<CorrectedModel> corrected;  // with bias correction (its model moved to quantized)
  std::optional<ModelError> error;          // none: no held-out frames
  size_t output_bytes = 0, golden_pairs = 0;
  int golden_skipped = 0;  // held-out frames an executor here could not reproduce (a rounding tie)
  std::vector<std::pair<std::string, double>> timing;  // phase, seconds
  std::string tasks_table;  // fp32 vs int8 task accuracies (eval), empty if not run
  nlohmann::json tasks_json;
  std::string tasks_note;  // why task accuracies are missing, if they are
};

// "inf" / "-" for non-finite values; used by the sweep too.
std::string format_db(double db);
// JSON number, or null when not finite (JSON has no inf/NaN).
nlohmann::json json_number(double v);

std::string format_summary(const QuantizeRun& run);
nlohmann::json report_json(const QuantizeRun& run);
// Writes report.json, layers.csv and summary.txt into `dir` (created if needed).
Status write_report(const std::string& dir, const QuantizeRun& run);

// JSON string escaping for CSV cells that may hold commas or quotes.
std::string csv_cell(const std::string& s);

}  // namespace tlvlink::quantize
