#pragma once
// `tlvlink quantize` as one library call: calibration on real or simulated frames (through the
// deployment preprocessing), int8 conversion with mixed-precision fallback and empirical bias
// correction, golden pairs from held-out frames, the quantized model written (after the loader
// and XNNPACK accepted it), the per-layer / end-to-end error on held-out frames, optionally fp32
// vs int8 task accuracies (tools/eval) and the report files.
//
//   QuantizeOptions o;
//   o.model_path = "enc-fp32.tlvm";  o.output_path = "enc-int8.tlvm";
//   o.data.path = "/data/t100k";     o.data.split = datasets::Split::kTrain;
//   auto run = run_quantize(o);      // Result<QuantizeRun>
//   std::fputs(format_summary(*run).c_str(), stdout);   // report.h

#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/quantize/calib_data.h"
#include "tlvlink/quantize/calibration_method.h"
#include "tlvlink/quantize/observer.h"
#include "tlvlink/quantize/quantizer.h"
#include "tlvlink/quantize/report.h"
#include "tlvlink/quantize/task_compare.h"

namespace tlvlink::quantize {

struct QuantizeOptions {
  std::string model_path;          // float .tlvm
  std::string output_path;         // int8 .tlvm to write
  std::string report_dir;          // empty: no report files
  CalibDataOptions data;           // where calibration and held-out frames come from
  CalibrationOptions calibration;  // method and percentile (validated here)
  double averaging_constant = TensorObserver::kDefaultAveragingConstant;  // method ema
  // Weights, --keep-float names ("first" / "last" or operator names, checked against the
  // model), bias-scale raise limit, clamp fusion.
  QuantizerOptions quantizer;
  int golden_pairs = 2;             // from the held-out frames
  int bias_correction_frames = 64;  // 0: off
  TaskEvalOptions tasks;            // requested(): fp32 vs int8 task accuracies
  bool progress = true;             // progress lines on stderr (else one summary per phase)
};

// Errors (nothing is written then): the model does not load or has no such --keep-float
// operator (kInvalidArgument), bad calibration options, unusable data (context "calibration
// data"), a quantizer failure, the quantized model failing to load or being refused by XNNPACK
// (a quantizer bug), and I/O errors writing the model or the report.
Result<QuantizeRun> run_quantize(const QuantizeOptions& options);

// "encoder-fp32" -> "encoder-int8"; "encoder" -> "encoder-int8"; "x-int8" stays.
std::string int8_model_name(const std::string& name);

}  // namespace tlvlink::quantize
