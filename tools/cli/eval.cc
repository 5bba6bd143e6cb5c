// tlvlink eval MODEL --touch DIR [--grasp DIR] [--compare OTHER.tlvm] [--bound LABEL=M.tlvm]
// [--record OUT.tlvm] [--json]: task accuracy on the test split as a table like TLV-Link's
// Table 2 (linear probe, the model's heads, zero-shot), optionally recorded in the model's heads.

#include <cstdio>
#include <memory>
#include <vector>

#include "eval_flags.h"
#include "tlvlink/eval/run.h"

namespace tlvlink::cli {
namespace {

struct EvalCommand {
  eval::EvalJob job;
  EvalFlags flags;
  bool json = false;
  bool no_paper = false;
  bool no_model_heads = false;
};

int run_eval(EvalCommand& c) {
  const char* command = "eval";
  auto data = c.flags.data();
  if (!data.ok()) return report_error(command, data.error());
  auto options = c.flags.options();
  if (!options.ok()) return report_error(command, options.error());
  options->model_heads = !c.no_model_heads;
  c.job.data = std::move(data).value();
  c.job.options = std::move(options).value();
  datasets::ProblemEcho problems("tlvlink eval", stderr, 10, c.flags.problems);
  c.job.data.problems = &problems;
  auto run = eval::run_eval(c.job);
  const Status shown = problems.finish();
  if (!run.ok()) return report_error(command, run.error());
  if (!shown.ok()) return report_error(command, shown.error());
  if (!c.job.record_path.empty()) {
    std::fprintf(stderr, "recorded the heads' test accuracy in %s:\n", c.job.record_path.c_str());
    for (const std::string& l : run->trust_lines) std::fprintf(stderr, "  %s\n", l.c_str());
  }
  std::vector<const eval::EvalReport*> views;
  for (const eval::EvalReport& r : run->reports) views.push_back(&r);
  if (c.json) {
    std::printf("%s\n", eval::report_json(views).c_str());
  } else {
    std::printf("%s", eval::format_table(views, !c.no_paper).c_str());
  }
  return kExitOk;
}

}  // namespace

void add_eval_command(CLI::App& app, int& exit_code) {
  auto c = std::make_shared<EvalCommand>();
  CLI::App* cmd = app.add_subcommand(
      "eval",
      "Task accuracy on the test split (material, hard/soft, rough/smooth, grasp): linear probes "
      "fitted on runtime embeddings, the model's own heads, zero-shot; a table like TLV-Link's "
      "Table 2");
  cmd->add_option("model", c->job.model_path, "Model file (.tlvm): fp32, ONNX-imported or int8")
      ->required();
  c->flags.add_to(*cmd);
  cmd->add_option("--compare", c->job.compare_path,
                  "A second model evaluated on the same data, side by side (e.g. fp32 vs int8)");
  cmd->add_option("--bound", c->job.bounds,
                  "LABEL=MODEL.tlvm: a reference model (e.g. a supervised upper bound) scored on "
                  "the same data with its own heads (else linear probes fitted on this data), "
                  "printed as a row 'bound: LABEL' (repeatable)");
  cmd->add_option("--record", c->job.record_path,
                  "Write a copy of MODEL whose heads record the measured test accuracy, the "
                  "majority-class rate and the set (runtime: head_trust.h); zero-shot heads that "
                  "do not beat the majority class are left out of the copy");
  cmd->add_flag("--keep-untrusted-zero-shot", c->job.keep_untrusted_zero_shot,
                "--record: keep zero-shot heads that do not beat the majority class");
  cmd->add_flag("--json", c->json, "Print machine-readable JSON");
  cmd->add_flag("--no-paper", c->no_paper, "Leave out the paper's reference rows");
  cmd->add_flag("--no-model-heads", c->no_model_heads, "Do not score the model's stored heads");
  cmd->footer(kExitCodeFooter);
  cmd->callback([c, &exit_code] { exit_code = run_eval(*c); });
}

}  // namespace tlvlink::cli
