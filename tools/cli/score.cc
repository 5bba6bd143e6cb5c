// `tlvlink score`: a live run of tlvlinkd against the ground truth of the scenario it played.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "common.h"
#include "tlvlink/score/score.h"

namespace tlvlink::cli {
namespace {

struct ScoreFlags {
  std::string truth, predictions;
  std::vector<std::string> fingers = {"left", "right"};
  bool json = false;
};

int run_score(const ScoreFlags& f) {
  auto r = score::score_live_run(f.truth, f.predictions, f.fingers);
  if (!r.ok()) return report_error("score", r.error());
  std::printf("%s\n", f.json ? score::format_score_json(*r).c_str() : score::format_score(*r).c_str());
  return kExitOk;
}

}  // namespace

void add_score_command(CLI::App& app, int& exit_code) {
  auto f = std::make_shared<ScoreFlags>();
  CLI::App* cmd = app.add_subcommand(
      "score",
      "Score tlvlinkd's JSON-lines output against the ground truth of the scenario it played "
      "(tlvlink sim scenario): contact gating misses and savings, per-frame heads, grasps");
  cmd->add_option("--truth", f->truth, "The scenario's truth.jsonl")->required();
  cmd->add_option("--predictions", f->predictions, "tlvlinkd's JSON-lines output")->required();
  cmd->add_option("--fingers", f->fingers, "The daemon's sensor names of finger A and B")
      ->delimiter(',')
      ->expected(2)
      ->capture_default_str();
  cmd->add_flag("--json", f->json, "One JSON object instead of the table");
  cmd->footer(kExitCodeFooter);
  cmd->callback([f, &exit_code] { exit_code = run_score(*f); });
}

}  // namespace tlvlink::cli
