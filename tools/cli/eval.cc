// tlvlink eval MODEL --touch DIR [--grasp DIR] [--compare OTHER.tlvm] [--json]: task accuracy on
// the test split as a table like TLV-Link's Table 2 (linear probe, the model's heads, zero-shot).

#include <cstdio>
#include <memory>
#include <vector>

#include "eval_flags.h"
#include "tlvlink/eval/run.h"

namespace tlvlink::cli {
namespace {

struct EvalCommand {
  std::string model, compare;
  EvalFlags flags;
  bool json = false;
  bool no_paper = false;
  bool no_model_heads = false;
};

int run_eval(const EvalCommand& c) {
  const char* command = "eval";
  auto data = c.flags.data();
  if (!data.ok()) return report_error(command, data.error());
  auto options = c.flags.options();
  if (!options.ok()) return report_error(command, options.error());
  options->model_heads = !c.no_model_heads;
  std::vector<std::string> paths{c.model};
  if (!c.compare.empty()) paths.push_back(c.compare);
  auto reports = eval::evaluate_files(paths, *data, *options);
  if (!reports.ok()) return report_error(command, reports.error());
  std::vector<const eval::EvalReport*> views;
  for (const eval::EvalReport& r : *reports) views.push_back(&r);
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
  cmd->add_option("model", c->model, "Model file (.tlvm): fp32, ONNX-imported or int8")
      ->required();
  c->flags.add_to(*cmd);
  cmd->add_option("--compare", c->compare,
                  "A second model evaluated on the same data, side by side (e.g. fp32 vs int8)");
  cmd->add_flag("--json", c->json, "Print machine-readable JSON");
  cmd->add_flag("--no-paper", c->no_paper, "Leave out the paper's reference rows");
  cmd->add_flag("--no-model-heads", c->no_model_heads, "Do not score the model's stored heads");
  cmd->footer(kExitCodeFooter);
  cmd->callback([c, &exit_code] { exit_code = run_eval(*c); });
}

}  // namespace tlvlink::cli
