// tlvlink heads fit MODEL --touch DIR [--grasp DIR] -o OUT.tlvm: linear probes + grasp head fitted
// on the runtime's embeddings of the train split, written into a copy of the model (same graph,
// new metadata), plus zero-shot heads from the text encoder where the model has none.
// tlvlink heads fit MODEL --images DIR --head NAME -o OUT.tlvm: a head of the user's own from
// labelled frames (DIR/<class>/...), validated by grouped cross-validation (eval/user_head.h).
// tlvlink heads fit MODEL --presses DIR,DIR... -o OUT.tlvm: a press head (hard/soft from how a
// press's imprint changes) from presses tlvlinkd recorded with embeddings (eval/press_head.h).

#include <cstdio>
#include <filesystem>
#include <memory>

#include "eval_flags.h"
#include "tlvlink/eval/press_head.h"
#include "tlvlink/eval/run.h"
#include "tlvlink/eval/trust.h"
#include "tlvlink/eval/user_head.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/sensor_frame.h"

namespace tlvlink::cli {
namespace {

struct HeadsFitCommand {
  std::string model, output;
  EvalFlags flags;
  bool one_grasp_head = false;
  bool no_zero_shot = false;
  bool keep_untrusted_zero_shot = false;
  std::vector<std::string> only;  // --only: the heads to fit (the others are kept)
  // --images: a head of the user's own
  std::string images, recordings, head, sensor;
  std::vector<std::string> presses;  // --presses: recorded press scenarios
  std::vector<std::string> press_predictions = {"press.jsonl"};
  int folds = 5, stride = 1;
  bool learning_curve = false, overwrite = false;
};

int run_user_head_fit(const HeadsFitCommand& c) {
  const char* command = "heads fit";
  if (!c.flags.touch.empty() || !c.flags.grasp.empty()) {
    return report_error(command,
                        Error::make(ErrorCode::kInvalidArgument,
                                    "--images fits one head of your own; --touch / "
                                    "--grasp fit the built-in heads: give one or the other"));
  }
  if (c.head.empty()) {
    return report_error(command, Error::make(ErrorCode::kInvalidArgument,
                                             "--images needs --head NAME (e.g. roughness, slip)"));
  }
  auto model = load_model(c.model);
  if (!model.ok()) return report_error(command, model.error());
  if (!c.images.empty() && !c.recordings.empty()) {
    return report_error(command, Error::make(ErrorCode::kInvalidArgument,
                                             "--images and --recordings: give one of them"));
  }
  auto frames = c.recordings.empty() ? eval::read_labelled_folder(c.images)
                                     : eval::read_labelled_recordings(c.recordings, c.stride);
  if (!frames.ok()) return report_error(command, frames.error());
  for (const std::string& s : frames->skipped)
    std::fprintf(stderr, "note: skipped %s\n", s.c_str());
  eval::UserHeadOptions o;
  o.head = c.head;
  o.sensor = c.sensor;
  o.cv.folds = c.folds;
  o.cv.logistic.max_iterations = c.flags.max_iterations;
  o.embedder.executor = c.flags.exec.kind();
  o.embedder.threads = c.flags.exec.threads;
  o.learning_curve = c.learning_curve;
  auto fit = eval::fit_user_head(**model, *frames, o);
  if (!fit.ok()) return report_error(command, fit.error());
  bool replaced = false;
  auto bytes = eval::model_with_user_head(**model, fit->head, &replaced);
  if (!bytes.ok()) return report_error(command, bytes.error());
  if (Status s = tools::write_file(c.output, *bytes); !s.ok())
    return report_error(command, s.error());
  std::fputs(eval::format_user_head(*frames, *fit).c_str(), stdout);
  std::printf("%s\n", eval::trust_decision_line(c.head, replaced, fit->head.trust,
                                                "it does not beat the pixel baseline, ")
                          .c_str());
  std::printf("wrote %s (%zu bytes)%s\n", c.output.c_str(), bytes->size(),
              (*model)->integrity().is_signed ? "; the model was signed, the copy is not: sign it "
                                                "with `tlvlink sign`"
                                              : "");
  return kExitOk;
}

int run_press_head_fit(const HeadsFitCommand& c) {
  const char* command = "heads fit";
  if (!c.flags.touch.empty() || !c.flags.grasp.empty() || !c.images.empty() ||
      !c.recordings.empty()) {
    return report_error(command, Error::make(ErrorCode::kInvalidArgument,
                                             "--presses fits the press head alone: give it "
                                             "without --touch, --grasp, --images, --recordings"));
  }
  auto model = load_model(c.model);
  if (!model.ok()) return report_error(command, model.error());
  eval::PressHeadOptions o;
  if (!c.head.empty()) o.head = c.head;
  o.predictions = c.press_predictions;
  o.cv.folds = c.folds;
  o.cv.logistic.max_iterations = c.flags.max_iterations;
  auto fit = eval::fit_press_head(**model, c.presses, o);
  if (!fit.ok()) return report_error(command, fit.error());
  bool replaced = false;
  auto bytes = eval::model_with_press_head(**model, fit->head, &replaced);
  if (!bytes.ok()) return report_error(command, bytes.error());
  if (Status s = tools::write_file(c.output, *bytes); !s.ok())
    return report_error(command, s.error());
  std::fputs(eval::format_press_head(*fit).c_str(), stdout);
  std::printf("%s\n", eval::trust_decision_line(o.head, replaced, fit->head.trust,
                                                "it does not beat one frame (the peak alone), ")
                          .c_str());
  std::printf("wrote %s (%zu bytes)\n", c.output.c_str(), bytes->size());
  return kExitOk;
}

int run_heads_fit(const HeadsFitCommand& c) {
  const char* command = "heads fit";
  // Checked before any fitting: a run of minutes must not end by replacing someone's file.
  if (!c.overwrite && std::filesystem::exists(c.output)) {
    return report_error(
        command,
        Error::make(ErrorCode::kIo, "%s exists; pass --overwrite to replace it", c.output.c_str()));
  }
  if (!c.presses.empty()) return run_press_head_fit(c);
  if (!c.images.empty() || !c.recordings.empty()) return run_user_head_fit(c);
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
  job.options.heads.grasp_per_sensor = !c.one_grasp_head;
  for (const std::string& name : c.only) {
    auto task = eval::parse_task(name);
    if (!task.ok())
      return report_error(command, task.error().with_context("--only %s", name.c_str()));
    job.options.heads.only.insert(*task);
  }
  job.keep_untrusted_zero_shot = c.keep_untrusted_zero_shot;
  job.on_note = [](const std::string& note) { std::fprintf(stderr, "note: %s\n", note.c_str()); };
  auto r = eval::fit_heads_into_file(job);
  if (!r.ok()) return report_error(command, r.error());
  std::string sensors;
  for (const auto& h : r->heads.sensor_grasp)
    sensors += (sensors.empty() ? "" : ", ") + h.sensors[0];
  std::printf("wrote %s (%zu bytes): %zu linear heads%s%s%s%s\n", c.output.c_str(), r->bytes,
              r->heads.linear.size(), r->heads.grasp ? " + grasp head" : "",
              sensors.empty() ? "" : " + a grasp head per sensor model (", sensors.c_str(),
              sensors.empty() ? "" : ")");
  for (const auto& [task, p] : r->heads.probes) {
    const eval::TaskResult* t = r->score.find(task, eval::Method::kModelHeads);
    std::printf("  %-13s l2=%-7g train acc %.3f (%lld rows)", eval::task_name(task), p.l2,
                p.train_accuracy, static_cast<long long>(p.train_rows));
    if (t != nullptr && t->available) {
      std::printf("  test acc %.3f (n=%lld)", t->accuracy, static_cast<long long>(t->n));
    }
    if (!p.view_trials.empty()) {
      for (const eval::ViewWeightTrial& v : p.view_trials) {
        if (v.view_weight == p.view_weight)
          std::printf("  view weight %g (validation: %.1f %% of frame/re-encoding pairs agree)",
                      v.view_weight, 100 * v.agreement);
      }
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
  cmd->add_flag("--one-grasp-head", c->one_grasp_head,
                "Fit only the grasp head for every sensor, not also one per sensor model when "
                "the grasp set holds several");
  cmd->add_option("--only", c->only,
                  "Fit only these heads (material, hard_soft, rough_smooth, grasp; the grasp "
                  "head brings its per-sensor ones) and keep the model's others as they are")
      ->delimiter(',');
  cmd->add_flag("--no-zero-shot", c->no_zero_shot,
                "Do not add zero-shot heads for tasks the model has none for");
  cmd->add_flag("--keep-untrusted-zero-shot", c->keep_untrusted_zero_shot,
                "Keep zero-shot heads that do not beat the majority class on the test split "
                "(default: left out)");
  cmd->add_option("--images", c->images,
                  "Fit one head of your own from labelled frames: DIR/<class>/*.png|jpg (classes "
                  "are the folder names), grouped by DIR/groups.tsv (<class>/<file><TAB><group>) "
                  "or by DIR/<class>/<group>/ folders; validated by grouped cross-validation");
  cmd->add_option("--recordings", c->recordings,
                  "Fit one head of your own from camera recordings (.tlvraw) named in a labels "
                  "file: <recording><TAB><class>[<TAB><from_s><TAB><to_s>][<TAB><group>] per "
                  "line; frames decoded by the daemon's decoder in the sensor's view; groups: "
                  "the recordings");
  cmd->add_option("--presses", c->presses,
                  "Fit the press head (hard/soft from a press's peak and its change from the "
                  "first frame in contact) from recorded presses: folders each with a scenario's "
                  "truth.jsonl and tlvlinkd's JSON lines of it with `embedding = true`, made with "
                  "this model; validated by recording (tools/eval/README.md \"Press head\")")
      ->delimiter(',');
  cmd->add_option("--press-predictions", c->press_predictions,
                  "With --presses: tlvlinkd's output file names in each folder, one play of the "
                  "scenario each (e.g. its live path and its exact frames); default press.jsonl")
      ->delimiter(',');
  cmd->add_option("--stride", c->stride, "With --recordings: keep every N-th frame")
      ->check(CLI::Range(1, 100000));
  cmd->add_option(
      "--head", c->head,
      "With --images / --recordings: the head's name (a linear head of that name is replaced); "
      "with --presses: the press head's (default hard_soft_press)");
  cmd->add_option("--sensor", c->sensor,
                  "With --images: the sensor the frames come from (" + tools::known_sensor_names() +
                      "); default: detected from each frame's size");
  cmd->add_option("--folds", c->folds, "With --images / --presses: cross-validation folds, at most")
      ->check(CLI::Range(2, 50));
  cmd->add_flag("--learning-curve", c->learning_curve,
                "With --images: also print how accuracy grows with the labelled groups per class");
  cmd->add_flag("--overwrite", c->overwrite,
                "Replace an existing output file (refused without it)");
  cmd->footer(kExitCodeFooter);
  cmd->callback([c, &exit_code] { exit_code = run_heads_fit(*c); });
}

}  // namespace tlvlink::cli
