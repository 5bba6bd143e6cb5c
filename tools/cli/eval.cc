// tlvlink eval MODEL --touch DIR [--grasp DIR] [--compare OTHER.tlvm] [--bound LABEL=M.tlvm]
// [--record OUT.tlvm] [--json]: task accuracy on the test split as a table like TLV-Link's
// Table 2 (linear probe, the model's heads, zero-shot), optionally recorded in the model's heads.
// tlvlink eval MODEL --images DIR --head NAME: one of the model's heads on labelled frames
// (DIR/<class>/..., eval/labelled_frames.h), e.g. a fitted head on objects it has not seen.

#include <cstdio>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "eval_flags.h"
#include "tlvlink/eval/run.h"
#include "tlvlink/eval/user_head.h"
#include "tlvlink/head_trust.h"
#include "tlvlink/inspect/trust_text.h"
#include "tlvlink/io/sensor_frame.h"

namespace tlvlink::cli {
namespace {

struct EvalCommand {
  eval::EvalJob job;
  EvalFlags flags;
  bool json = false;
  bool no_paper = false;
  bool no_model_heads = false;
  std::string images, recordings, head, sensor;
};

// One head on labelled frames, beside the accuracy its trust record claims.
int run_eval_images(const EvalCommand& c) {
  const char* command = "eval";
  if (c.head.empty()) {
    return report_error(command, Error::make(ErrorCode::kInvalidArgument,
                                             "--images needs --head NAME (one of the model's "
                                             "linear heads)"));
  }
  auto model = load_model(c.job.model_path);
  if (!model.ok()) return report_error(command, model.error());
  auto frames = c.recordings.empty() ? eval::read_labelled_folder(c.images)
                                     : eval::read_labelled_recordings(c.recordings);
  if (!frames.ok()) return report_error(command, frames.error());
  for (const std::string& s : frames->skipped)
    std::fprintf(stderr, "note: skipped %s\n", s.c_str());
  eval::EmbedderOptions eo;
  eo.executor = c.flags.exec.kind();
  eo.threads = c.flags.exec.threads;
  auto features = eval::frame_features(**model, *frames, c.sensor, eo);
  if (!features.ok()) return report_error(command, features.error());
  auto score = eval::score_model_head(**model, *features, *frames, c.head);
  if (!score.ok()) return report_error(command, score.error());
  const Metadata& m = (*model)->metadata();
  const LinearHead* head = nullptr;  // score_model_head found it: it exists
  for (const LinearHead& h : m.linear_heads)
    if (h.name == c.head) head = &h;
  const HeadTrust* recorded = &head->trust;
  const bool has_interval = recorded->present && recorded->ci_low >= 0;
  const bool within = has_interval &&
                      score->accuracy >= static_cast<double>(recorded->ci_low) - 1e-6 &&
                      score->accuracy <= static_cast<double>(recorded->ci_high) + 1e-6;
  std::string answers;
  for (size_t k = 0; k < score->predicted_counts.size(); ++k) {
    answers += (answers.empty() ? "" : ", ") + std::string(head->labels[k]) + " " +
               std::to_string(score->predicted_counts[k]);
  }
  if (c.json) {
    nlohmann::json j = {{"head", c.head},
                        {"images", c.images},
                        {"n", score->n},
                        {"groups", score->groups},
                        {"accuracy", score->accuracy},
                        {"accuracy_ci95", {score->ci_low, score->ci_high}},
                        {"balanced_accuracy", score->balanced_accuracy},
                        {"majority", score->majority},
                        {"answers", score->predicted_counts},
                        {"recorded", inspect::trust_text(*recorded, true)},
                        {"within_recorded_interval",
                         has_interval ? nlohmann::json(within) : nlohmann::json(nullptr)}};
    std::printf("%s\n", j.dump(2).c_str());
    return kExitOk;
  }
  std::printf("head '%s' on %s: %lld frames, %lld groups (grouping: %s); read as %s\n",
              c.head.c_str(), c.images.c_str(), static_cast<long long>(score->n),
              static_cast<long long>(score->groups), eval::grouping_name(frames->grouping),
              features->view_note.c_str());
  std::printf(
      "  accuracy %.1f %% [%.1f, %.1f] (95 %%, groups resampled)  balanced %.1f %%  "
      "majority %.1f %%\n",
      100 * score->accuracy, 100 * score->ci_low, 100 * score->ci_high,
      100 * score->balanced_accuracy, 100 * score->majority);
  std::printf("  answers: %s\n", answers.c_str());
  std::printf("  recorded: %s\n", inspect::trust_text(*recorded, true).c_str());
  if (has_interval) {
    std::printf("  the accuracy here is %s the recorded interval\n", within ? "within" : "OUTSIDE");
  }
  return kExitOk;
}

int run_eval(EvalCommand& c) {
  if (!c.images.empty() || !c.recordings.empty()) return run_eval_images(c);
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
  cmd->add_option(
      "--images", c->images,
      "Score one of the model's heads (--head) on labelled frames: DIR/<class>/*.png|jpg, "
      "class folders named after the head's labels (groups as `heads fit --images`)");
  cmd->add_option("--recordings", c->recordings,
                  "Score one of the model's heads (--head) on camera recordings named in a labels "
                  "file (as `heads fit --recordings`)");
  cmd->add_option("--head", c->head, "With --images / --recordings: the linear head to score");
  cmd->add_option("--sensor", c->sensor,
                  "With --images: the sensor the frames come from (" + tools::known_sensor_names() +
                      "); default: detected from each frame's size");
  cmd->footer(kExitCodeFooter);
  cmd->callback([c, &exit_code] { exit_code = run_eval(*c); });
}

}  // namespace tlvlink::cli
