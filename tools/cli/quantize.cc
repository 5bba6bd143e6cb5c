// tlvlink quantize FLOAT.tlvm --calib DATA -o INT8.tlvm: flags -> quantize::run_quantize (the
// pipeline in tools/quantize) -> the summary on stdout.

#include <cstdio>

#include "common.h"
#include "quantize_flags.h"
#include "tlvlink/quantize/pipeline.h"

namespace tlvlink::cli {
namespace {

struct QuantizeFlags {
  std::string model, output, report_dir;
  QuantizeDataFlags data;
  std::string method = "percentile";
  double percentile = 99.99;
  std::string weights = "per-channel";
  std::vector<std::string> keep_float;
  double max_bias_raise = 16.0;
  bool no_fuse = false;
  int golden = 2;
  int bias_correction_frames = 64;
  quantize::TaskEvalOptions tasks;
  bool quiet = false;
};

int run_quantize(const QuantizeFlags& f) {
  const char* cmd = "quantize";
  quantize::QuantizeOptions o;
  o.model_path = f.model;
  o.output_path = f.output;
  o.report_dir = f.report_dir;
  o.data = f.data.options();
  datasets::ProblemEcho problems("tlvlink quantize", stderr, 10, f.data.problems);
  o.data.problems = &problems;
  o.averaging_constant = f.data.averaging_constant;
  auto method = quantize::parse_calibration_method(f.method);
  if (!method.ok()) return report_error(cmd, method.error());
  o.calibration.method = *method;
  o.calibration.percentile = f.percentile;
  o.quantizer.weights = f.weights == "per-tensor" ? quantize::WeightGranularity::kPerTensor
                                                  : quantize::WeightGranularity::kPerChannel;
  o.quantizer.keep_float = f.keep_float;
  o.quantizer.max_bias_scale_raise = f.max_bias_raise;
  o.quantizer.fuse_clamps = !f.no_fuse;
  o.golden_pairs = f.golden;
  o.bias_correction_frames = f.bias_correction_frames;
  o.tasks = f.tasks;
  o.progress = !f.quiet;
  auto run = quantize::run_quantize(o);
  const Status shown = problems.finish();
  if (!run.ok()) return report_error(cmd, run.error());
  if (!shown.ok()) return report_error(cmd, shown.error());
  std::fputs(quantize::format_summary(*run).c_str(), stdout);
  if (!f.report_dir.empty())
    std::printf("  %-12s %s/{report.json,layers.csv,summary.txt}\n", "report",
                f.report_dir.c_str());
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
  cmd->add_option("model", f->model,
                  "Float model (.tlvm), e.g. from gen-reference --dtype fp32, "
                  "convert or the trainer's export")
      ->required();
  cmd->add_option("-o,--output", f->output, "Output int8 model (.tlvm)")->required();
  f->data.add_to(*cmd);
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
  cmd->add_flag("--no-fuse", f->no_fuse,
                "Do not fuse standalone ReLU/ReLU6 clamps into the op before");
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
