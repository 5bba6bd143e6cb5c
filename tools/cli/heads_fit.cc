// tlvlink heads fit MODEL --touch DIR [--grasp DIR] -o OUT.tlvm: linear probes + grasp head fitted
// on the runtime's embeddings of the train split, written into a copy of the model (same graph,
// new metadata), plus zero-shot heads from the text encoder where the model has none.

#include <cstdio>
#include <memory>

#include "eval_flags.h"
#include "tlvlink/eval/run.h"

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
  eval::HeadsFitJob job;
  auto data = c.flags.data();
  if (!data.ok()) return report_error(command, data.error());
  auto options = c.flags.options();
  if (!options.ok()) return report_error(command, options.error());
  job.model_path = c.model;
  job.output_path = c.output;
  job.data = std::move(data).value();
  job.options = std::move(options).value();
  job.add_missing_zero_shot = !c.no_zero_shot;
  job.keep_untrusted_zero_shot = c.keep_untrusted_zero_shot;
  job.on_note = [](const std::string& note) { std::fprintf(stderr, "note: %s\n", note.c_str()); };
  auto r = eval::fit_heads_into_file(job);
  if (!r.ok()) return report_error(command, r.error());
  std::printf("wrote %s (%zu bytes): %zu linear heads%s\n", c.output.c_str(), r->bytes,
              r->heads.linear.size(), r->heads.grasp ? " + grasp head" : "");
  for (const auto& [task, p] : r->heads.probes) {
    const eval::TaskResult* t = r->score.find(task, eval::Method::kModelHeads);
    std::printf("  %-13s l2=%-7g train acc %.3f (%lld rows)", eval::task_name(task), p.l2,
                p.train_accuracy, static_cast<long long>(p.train_rows));
    if (t != nullptr && t->available) {
      std::printf("  test acc %.3f (n=%lld)", t->accuracy, static_cast<long long>(t->n));
    }
    std::printf("%s%s\n", p.note.empty() ? "" : "  ", p.note.c_str());
  }
  std::printf("trust (recorded in the heads; runtime rule: head_trust.h):\n");
  for (const std::string& l : r->trust_lines) std::printf("  %s\n", l.c_str());
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
