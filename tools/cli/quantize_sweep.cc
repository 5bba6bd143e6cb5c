// tlvlink quantize-sweep: flags -> quantize::run_sweep (tools/quantize: error against run time
// for each model and variant, CSV / JSON / SVG written) -> the table on stdout.

#include <cstdio>

#include "common.h"
#include "quantize_flags.h"
#include "tlvlink/quantize/sweep.h"

namespace tlvlink::cli {
namespace {

struct SweepFlags {
  std::vector<std::string> models;
  QuantizeDataFlags data;
  std::string out_dir;
  std::vector<int> threads = {1, 2};
  std::vector<std::string> methods = {"minmax", "ema", "percentile", "entropy", "mse"};
  std::vector<std::string> keep_float;
  double percentile = 99.99;
  int bias_correction_frames = 64;
  int runs = 50, warmup = 5;
  bool quiet = false;
};

int run_sweep(const SweepFlags& f) {
  const char* cmd = "quantize-sweep";
  quantize::SweepOptions o;
  o.methods.clear();
  for (const std::string& name : f.methods) {
    auto m = quantize::parse_calibration_method(name);
    if (!m.ok()) return report_error(cmd, m.error());
    o.methods.push_back(*m);
  }
  o.models = f.models;
  o.data = f.data.options();
  datasets::ProblemEcho problems("tlvlink quantize-sweep", stderr, 10, f.data.problems);
  o.data.problems = &problems;
  o.averaging_constant = f.data.averaging_constant;
  o.out_dir = f.out_dir;
  o.threads = f.threads;
  o.keep_float = f.keep_float;
  o.percentile = f.percentile;
  o.bias_correction_frames = f.bias_correction_frames;
  o.runs = f.runs;
  o.warmup = f.warmup;
  o.progress = !f.quiet;
  o.on_note = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  auto r = quantize::run_sweep(o);
  const Status shown = problems.finish();
  if (!r.ok()) return report_error(cmd, r.error());
  if (!shown.ok()) return report_error(cmd, shown.error());
  std::fputs(quantize::sweep_table(o, *r).c_str(), stdout);
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
  cmd->add_option("--models", f->models,
                  "Float models (.tlvm), comma-separated (sizes / resolutions)")
      ->required()
      ->delimiter(',')
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", f->out_dir, "Output directory")->required();
  f->data.add_to(*cmd);
  cmd->add_option("--threads", f->threads, "Thread counts, comma-separated")
      ->delimiter(',')
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option("--methods", f->methods,
                  "Calibration methods (the first is also used for the per-tensor row)")
      ->delimiter(',')
      ->check(CLI::IsMember({"minmax", "ema", "percentile", "entropy", "mse"}))
      ->capture_default_str();
  cmd->add_option(
         "--keep-float", f->keep_float,
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
  cmd->footer(
      std::string(kExitCodeFooter) +
      "\nExample: tlvlink quantize-sweep --models enc96.tlvm,enc128.tlvm --calib /data/t100k "
      "-o /tmp/sweep --threads 1,2");
  cmd->callback([f, &exit_code] { exit_code = run_sweep(*f); });
}

}  // namespace tlvlink::cli
