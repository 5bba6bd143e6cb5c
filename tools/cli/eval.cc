// tlvlink eval MODEL --touch DIR [--grasp DIR] [--compare OTHER.tlvm] [--json]: task accuracy on
// the test split as a table like TLV-Link's Table 2 (linear probe, the model's heads, zero-shot).

#include <cstdio>
#include <memory>

#include "cli/eval_flags.h"
#include "tlvlink/io/file.h"
#include "tlvlink/eval/trust.h"

namespace tlvlink::cli {
namespace {

struct EvalCommand {
  std::string model, compare;
  std::vector<std::string> bounds;  // LABEL=MODEL
  std::string record;               // write a copy of the model with trust records here
  bool keep_untrusted_zero_shot = false;
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

// A reference model's row (e.g. a supervised upper bound) on the same data: its own heads when
// it has them (fitted like the evaluated model's, e.g. by `heads fit` on the same heads' set),
// else linear probes fitted on this data's training split.
Result<eval::BoundRow> bound_row(const std::string& spec, const eval::EvalData& data,
                                 eval::EvalOptions o) {
  const size_t eq = spec.find('=');
  TLV_ENSURE(eq != std::string::npos && eq > 0 && eq + 1 < spec.size(),
             ErrorCode::kInvalidArgument, "--bound '%s': expected LABEL=MODEL.tlvm", spec.c_str());
  eval::BoundRow b;
  b.label = spec.substr(0, eq);
  b.model_path = spec.substr(eq + 1);
  o.model_heads = true;
  o.zero_shot = eval::ZeroShotSource::kModel;
  o.oracle_samples = 0;
  o.touch_oracles = false;
  TLV_ASSIGN_OR_RETURN(eval::EvalReport r, evaluate_one(b.model_path, data, o));
  b.model_name = r.model_name;
  for (eval::Task t : eval::kAllTasks) {
    const eval::TaskResult* heads = r.find(t, eval::Method::kModelHeads);
    const eval::TaskResult* probe = r.find(t, eval::Method::kProbe);
    if (heads != nullptr && heads->available) b.results.push_back(*heads);
    else if (probe != nullptr) b.results.push_back(*probe);
  }
  return b;
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
  for (const std::string& spec : c.bounds) {
    auto b = bound_row(spec, *data, *options);
    if (!b.ok()) return report_error(command, b.error());
    first->bounds.push_back(std::move(b).value());
  }
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
  if (!c.record.empty()) {
    auto model = load_model(c.model);
    if (!model.ok()) return report_error(command, model.error());
    std::vector<std::string> lines;
    eval::TrustRecordOptions ro;
    ro.drop_untrusted_zero_shot = !c.keep_untrusted_zero_shot;
    auto bytes = eval::model_with_trust(**model, *first, ro, &lines);
    if (!bytes.ok()) return report_error(command, bytes.error());
    if (Status s = tools::write_file(c.record, *bytes); !s.ok()) return report_error(command, s.error());
    std::fprintf(stderr, "recorded the heads' test accuracy in %s:\n", c.record.c_str());
    for (const std::string& l : lines) std::fprintf(stderr, "  %s\n", l.c_str());
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
  cmd->add_option("--bound", c->bounds,
                  "LABEL=MODEL.tlvm: a reference model (e.g. a supervised upper bound) scored on "
                  "the same data with its own heads (else linear probes fitted on this data), "
                  "printed as a row 'bound: LABEL' (repeatable)");
  cmd->add_option("--record", c->record,
                  "Write a copy of MODEL whose heads record the measured test accuracy, the "
                  "majority-class rate and the set (runtime: head_trust.h); zero-shot heads that "
                  "do not beat the majority class are left out of the copy");
  cmd->add_flag("--keep-untrusted-zero-shot", c->keep_untrusted_zero_shot,
                "--record: keep zero-shot heads that do not beat the majority class");
  cmd->add_flag("--json", c->json, "Print machine-readable JSON");
  cmd->add_flag("--no-paper", c->no_paper, "Leave out the paper's reference rows");
  cmd->add_flag("--no-model-heads", c->no_model_heads, "Do not score the model's stored heads");
  cmd->footer(kExitCodeFooter);
  cmd->callback([c, &exit_code] { exit_code = run_eval(*c); });
}

}  // namespace tlvlink::cli
