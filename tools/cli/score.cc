// `tlvlink score`: live runs of tlvlinkd against the ground truth of the scenarios they played,
// and, given the offline runs of the same scenarios, live against offline frame by frame.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "common.h"
#include "tlvlink/score/compare.h"
#include "tlvlink/score/score.h"

namespace tlvlink::cli {
namespace {

struct ScoreFlags {
  std::vector<std::string> truth, predictions, offline;
  std::vector<std::string> fingers = {"left", "right"};
  std::string reference = "offline";
  bool json = false;
};

int run_score(const ScoreFlags& f) {
  if (f.truth.size() != f.predictions.size() ||
      (!f.offline.empty() && f.offline.size() != f.truth.size())) {
    std::fprintf(stderr,
                 "tlvlink score: %zu --truth, %zu --predictions and %zu --offline files: give one "
                 "--predictions (and one --offline, if any) per --truth, in the same order\n",
                 f.truth.size(), f.predictions.size(), f.offline.size());
    return kExitUsage;
  }
  if (!f.offline.empty()) {
    std::vector<score::RunFiles> runs;
    for (size_t i = 0; i < f.truth.size(); ++i)
      runs.push_back({f.truth[i], f.predictions[i], f.offline[i]});
    auto r = score::compare_live_offline(runs, f.fingers);
    if (!r.ok()) return report_error("score", r.error());
    const auto ref =
        f.reference == "dataset" ? score::Reference::kDatasetCopy : score::Reference::kExactFrames;
    std::printf("%s\n",
                f.json
                    ? score::format_live_offline_json(*r, ref).c_str()
                    : (score::format_score(r->live) + score::format_live_offline(*r, ref)).c_str());
    return kExitOk;
  }
  score::ScoreReport pooled;
  for (size_t i = 0; i < f.truth.size(); ++i) {
    auto r = score::score_live_run(f.truth[i], f.predictions[i], f.fingers);
    if (!r.ok()) return report_error("score", r.error());
    if (f.truth.size() == 1) {
      pooled = std::move(*r);
    } else {
      score::merge_scores(pooled, *r);
    }
  }
  std::printf("%s\n", f.json ? score::format_score_json(pooled).c_str()
                             : score::format_score(pooled).c_str());
  return kExitOk;
}

}  // namespace

void add_score_command(CLI::App& app, int& exit_code) {
  auto f = std::make_shared<ScoreFlags>();
  CLI::App* cmd = app.add_subcommand(
      "score",
      "Score tlvlinkd's JSON-lines output against the ground truth of the scenario it played "
      "(tlvlink sim scenario): contact gating misses and savings, per-frame heads, grasps; "
      "several scenarios pool; with --offline, live against offline on the same frames");
  cmd->add_option("--truth", f->truth, "The scenario's truth.jsonl (repeatable)")->required();
  cmd->add_option("--predictions", f->predictions,
                  "tlvlinkd's JSON-lines output of the live run (one per --truth)")
      ->required();
  cmd->add_option("--offline", f->offline,
                  "tlvlinkd's output on the scenario's offline recordings (sim scenario "
                  "--offline; one per --truth): prints live vs offline per head and for grasps "
                  "with 95 % intervals (bootstrap over events)");
  cmd->add_option("--reference", f->reference,
                  "What the --offline runs replayed: offline (the scenes' processed frames "
                  "exactly; the targets apply) or dataset (the datasets' JPEG copy of them: "
                  "labelled so, no targets)")
      ->check(CLI::IsMember({"offline", "dataset"}))
      ->capture_default_str();
  cmd->add_option("--fingers", f->fingers, "The daemon's sensor names of finger A and B")
      ->delimiter(',')
      ->expected(2)
      ->capture_default_str();
  cmd->add_flag("--json", f->json, "One JSON object instead of the table");
  cmd->footer(kExitCodeFooter);
  cmd->callback([f, &exit_code] { exit_code = run_score(*f); });
}

}  // namespace tlvlink::cli
