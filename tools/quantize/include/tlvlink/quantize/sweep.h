#pragma once
// `tlvlink quantize-sweep` as a library call: error against run time. For each model and variant
// (fp32; int8 per-channel with the main method without bias correction; int8 with per-tensor
// weights; int8 per-channel with each calibration method; optionally a mixed-precision row) the
// embedding error on held-out frames (XNNPACK outputs against the fp32 reference executor) and
// the XNNPACK latency at each thread count, timed interleaved (tools/bench timing.h). Writes
// sweep.csv, sweep.json and sweep.svg (+ sweep.png when rsvg-convert is installed) into out_dir.
//
//   SweepOptions o;
//   o.models = {"enc96.tlvm", "enc128.tlvm"};  o.data.path = "/data/t100k";  o.out_dir = "sweep";
//   auto r = run_sweep(o);
//   std::fputs(sweep_table(o, *r).c_str(), stdout);

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tlvlink/bench/timing.h"
#include "tlvlink/error.h"
#include "tlvlink/quantize/calib_data.h"
#include "tlvlink/quantize/calibration_method.h"
#include "tlvlink/quantize/observer.h"
#include "tlvlink/quantize/quantizer.h"

namespace tlvlink::quantize {

struct SweepOptions {
  std::vector<std::string> models;  // float .tlvm files
  CalibDataOptions data;            // calibration and held-out frames (held-out count > 0)
  double averaging_constant = TensorObserver::kDefaultAveragingConstant;
  std::string out_dir;
  std::vector<int> threads = {1, 2};
  // Not empty; the first is also the per-tensor row's method. The "main" method (percentile
  // when swept, else the first) has the rows without bias correction and with keep_float.
  std::vector<CalibrationMethod> methods = {CalibrationMethod::kMinMax, CalibrationMethod::kEma,
                                            CalibrationMethod::kPercentile,
                                            CalibrationMethod::kEntropy, CalibrationMethod::kMse};
  std::vector<std::string> keep_float;  // not empty: one more row, mixed precision
  double percentile = 99.99;
  int bias_correction_frames = 64;  // 0: off
  int runs = 50, warmup = 5;
  bool progress = true;
  // One line per model ("quantize-sweep: M (HxW)") and per row measured; `tlvlink` prints them
  // on stderr.
  std::function<void(const std::string& line)> on_note;
};

struct SweepVariant {
  std::string name;
  bool fp32 = false;
  WeightGranularity weights = WeightGranularity::kPerChannel;
  CalibrationMethod method = CalibrationMethod::kMinMax;
  std::vector<std::string> keep_float;
  bool bias_correction = true;  // when the sweep corrects at all (bias_correction_frames > 0)
};
// The variants of a sweep, in row order.
std::vector<SweepVariant> sweep_variants(const std::vector<CalibrationMethod>& methods,
                                         const std::vector<std::string>& keep_float,
                                         bool bias_correction);

struct SweepRow {
  std::string model, model_name, resolution, variant, precision, weights, method;
  size_t bias_correction_frames = 0;
  size_t model_index = 0, variant_index = 0;
  double mmac = 0;
  int threads = 1;
  size_t int8_ops = 0, fp32_ops = 0, bytes = 0;
  double cos_mean = 0, cos_min = 0, sqnr_db = 0, max_abs = 0;
  bench::LatencyStats latency;
};

struct SweepResult {
  std::vector<SweepVariant> variants;
  std::vector<SweepRow> rows;
  double load_before = 0, load_after = 0;  // 1-minute load average
  bool png = false;                        // sweep.png written
};

// Errors: empty methods or models (kInvalidArgument), a model or its data (context
// "calibration data for M"), no held-out frames (kInvalidArgument), a quantizer or executor
// failure, I/O errors writing out_dir.
Result<SweepResult> run_sweep(const SweepOptions& options);

// The files' contents, and the table `tlvlink quantize-sweep` prints.
std::string sweep_csv(const SweepResult& result);
nlohmann::json sweep_json(const SweepOptions& options, const SweepResult& result);
std::string sweep_svg(const SweepOptions& options, const SweepResult& result);
std::string sweep_table(const SweepOptions& options, const SweepResult& result);

}  // namespace tlvlink::quantize
