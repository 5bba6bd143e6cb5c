// tlvlink eval MODEL --touch DIR [--grasp DIR] [--compare OTHER.tlvm] [--json]: task accuracy on
// the test split as a table like TLV-Link's Table 2 (linear probe, the model's heads, zero-shot).

#include <cstdio>
#include <memory>

#include "cli/eval_flags.h"

namespace tlvlink::cli {
namespace {

struct EvalCommand {
  std::string model, compare;
  EvalFlags flags;
  bool json = false;
  bool no_paper = false;
  bool no_model_heads = false;
};

Result<eval::EvalReport> evaluate_one(const std::string& path, const eval::EvalData& data,
                                      const eval::EvalOptions& options) {
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Model> model, load_model(path));
  auto report = eval::evaluate(*model, data, options);
  if (!report.ok()) return report.error().with_context("evaluating %s", path.c_str());
  report->model_path = path;
  return std::move(report).value();
}

int run_eval(const EvalCommand& c) {
  const char* command = "eval";
  auto data = c.flags.data();
  if (!data.ok()) return report_error(command, data.error());
  auto options = c.flags.options();
  if (!options.ok()) return report_error(command, options.error());
  options->model_heads = !c.no_model_heads;
  auto first = evaluate_one(c.model, *data, *options);
  if (!first.ok()) return report_error(command, first.error());
  std::vector<const eval::EvalReport*> reports{&*first};
  std::optional<eval::EvalReport> second;
  if (!c.compare.empty()) {
    eval::EvalOptions o = *options;
    o.oracle_samples = 0;  // the data is the same: one oracle estimate serves both
    auto r = evaluate_one(c.compare, *data, o);
    if (!r.ok()) return report_error(command, r.error());
    r->oracle = first->oracle;
    second = std::move(r).value();
    reports.push_back(&*second);
  }
  if (c.json) {
    std::printf("%s\n", eval::report_json(reports).c_str());
  } else {
    std::printf("%s", eval::format_table(reports, !c.no_paper).c_str());
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
