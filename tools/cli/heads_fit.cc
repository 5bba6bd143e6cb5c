// tlvlink heads fit MODEL --touch DIR [--grasp DIR] -o OUT.tlvm: linear probes + grasp head fitted
// on the runtime's embeddings of the train split, written into a copy of the model (same graph,
// new metadata), plus zero-shot heads from the text encoder where the model has none.

#include <cstdio>
#include <memory>

#include "cli/eval_flags.h"
#include "tlvlink/eval/trust.h"
#include "tlvlink/io/file.h"

namespace tlvlink::cli {
namespace {

struct HeadsFitCommand {
  std::string model, output;
  EvalFlags flags;
  bool no_zero_shot = false;
  bool keep_untrusted_zero_shot = false;
};

int run_heads_fit(const HeadsFitCommand& c) {
  const char* command = "heads fit";
  auto data = c.flags.data();
  if (!data.ok()) return report_error(command, data.error());
  auto options = c.flags.options();
  if (!options.ok()) return report_error(command, options.error());
  auto model = load_model(c.model);
  if (!model.ok()) return report_error(command, model.error());
  auto set = eval::extract_embeddings(**model, *data, options->embedder);
  if (!set.ok()) return report_error(command, set.error());
  auto heads = eval::fit_heads(*set, options->heads);
  if (!heads.ok()) return report_error(command, heads.error());
  for (const std::string& note : heads->notes) std::fprintf(stderr, "note: %s\n", note.c_str());
  if (heads->linear.empty() && !heads->grasp) {
    return report_error(command, Error::make(ErrorCode::kFormat,
                                             "no head could be fitted (no labelled training rows)"));
  }
  eval::WriteHeadsOptions wo;
  wo.add_missing_zero_shot = !c.no_zero_shot;
  wo.text = options->text;
  wo.provenance_note = "tlvlink heads fit";
  if (!data->touch_dir.empty()) wo.provenance_note += " --touch " + data->touch_dir;
  if (!data->grasp_dir.empty()) wo.provenance_note += " --grasp " + data->grasp_dir;
  auto bytes = eval::model_with_heads(**model, *heads, wo);
  if (!bytes.ok()) return report_error(command, bytes.error());
  // Score what was written, as the device applies it (the model's heads on the test split),
  // and record it in the heads (trust.h) before the file is written.
  auto written = Model::load(*bytes);
  if (!written.ok()) return report_error(command, written.error());
  eval::EvalOptions score = *options;
  score.fit_probes = false;
  score.model_heads = true;
  score.oracle_samples = 0;
  score.touch_oracles = false;
  auto report = eval::evaluate_embeddings((*written)->metadata(), *set, score);
  if (!report.ok()) return report_error(command, report.error());
  report->touch_dir = data->touch_dir;
  report->grasp_dir = data->grasp_dir;
  eval::TrustRecordOptions ro;
  ro.drop_untrusted_zero_shot = !c.keep_untrusted_zero_shot;
  std::vector<std::string> trust_lines;
  auto recorded = eval::model_with_trust(**written, *report, ro, &trust_lines);
  if (!recorded.ok()) return report_error(command, recorded.error());
  *bytes = std::move(recorded).value();
  if (Status s = tools::write_file(c.output, *bytes); !s.ok()) return report_error(command, s.error());
  std::printf("wrote %s (%zu bytes): %zu linear heads%s\n", c.output.c_str(), bytes->size(),
              heads->linear.size(), heads->grasp ? " + grasp head" : "");
  for (const auto& [task, p] : heads->probes) {
    const eval::TaskResult* r = report->find(task, eval::Method::kModelHeads);
    std::printf("  %-13s l2=%-7g train acc %.3f (%lld rows)", eval::task_name(task), p.l2,
                p.train_accuracy, static_cast<long long>(p.train_rows));
    if (r != nullptr && r->available) {
      std::printf("  test acc %.3f (n=%lld)", r->accuracy, static_cast<long long>(r->n));
    }
    std::printf("%s%s\n", p.note.empty() ? "" : "  ", p.note.c_str());
  }
  std::printf("trust (recorded in the heads; runtime rule: head_trust.h):\n");
  for (const std::string& l : trust_lines) std::printf("  %s\n", l.c_str());
  return kExitOk;
}

}  // namespace

void add_heads_command(CLI::App& app, int& exit_code) {
  CLI::App* heads = app.add_subcommand("heads", "Task heads of a model");
  heads->require_subcommand(1);
  auto c = std::make_shared<HeadsFitCommand>();
  CLI::App* cmd = heads->add_subcommand(
      "fit",
      "Fit linear probes (material, hard/soft, rough/smooth) and the grasp head on the runtime's "
      "embeddings of the train split; write a copy of the model with them (+ zero-shot heads)");
  cmd->add_option("model", c->model, "Model file (.tlvm)")->required();
  cmd->add_option("-o,--output", c->output, "Output model file (.tlvm)")->required();
  c->flags.add_to(*cmd);
  cmd->add_flag("--no-zero-shot", c->no_zero_shot,
                "Do not add zero-shot heads for tasks the model has none for");
  cmd->add_flag("--keep-untrusted-zero-shot", c->keep_untrusted_zero_shot,
                "Keep zero-shot heads that do not beat the majority class on the test split "
                "(default: left out)");
  cmd->footer(kExitCodeFooter);
  cmd->callback([c, &exit_code] { exit_code = run_heads_fit(*c); });
}

}  // namespace tlvlink::cli
