// tlvlink adapt MODEL --checkpoint CKPT --images DIR --head NAME: does adapting the encoder's
// last layer(s) to the user's frames beat the linear head, on the same grouped folds? Built
// with TLVLINK_BUILD_TRAINER (tools/trainer adapt.h).

#include <cstdio>
#include <memory>

#include "common.h"
#include "tlvlink/eval/labelled_frames.h"
#include "tlvlink/trainer/adapt.h"

namespace tlvlink::cli {
namespace {

struct AdaptCommand {
  std::string model, images, head, sensor;
  trainer::AdaptOptions options;
};

int run_adapt(const AdaptCommand& c) {
  const char* command = "adapt";
  auto model = load_model(c.model);
  if (!model.ok()) return report_error(command, model.error());
  auto frames = eval::read_labelled_folder(c.images);
  if (!frames.ok()) return report_error(command, frames.error());
  for (const std::string& s : frames->skipped)
    std::fprintf(stderr, "note: skipped %s\n", s.c_str());
  auto r = trainer::compare_adapted_head(**model, *frames, c.sensor, c.options);
  if (!r.ok()) return report_error(command, r.error());
  std::fputs(trainer::format_adapt_comparison(*r, c.head).c_str(), stdout);
  return kExitOk;
}

}  // namespace

void add_adapt_command(CLI::App& app, int& exit_code) {
  auto c = std::make_shared<AdaptCommand>();
  CLI::App* cmd = app.add_subcommand(
      "adapt",
      "Does adapting the encoder's last layer(s) to your labelled frames beat a linear "
      "head? Both scored on the same grouped folds (writes nothing)");
  cmd->add_option("model", c->model, "Float model exported from the checkpoint (.tlvm)")
      ->required();
  cmd->add_option("--checkpoint", c->options.checkpoint,
                  "The `tlvlink train` checkpoint the model was exported from")
      ->required();
  cmd->add_option("--images", c->images,
                  "Labelled frames: DIR/<class>/... (groups as `heads fit --images`)")
      ->required();
  cmd->add_option("--head", c->head, "Name of the head, for the report")->required();
  cmd->add_option("--sensor", c->sensor,
                  "Sensor model whose camera view the frames are (default: a processed view)");
  cmd->add_option("--layers", c->options.layers, "Conv layers adapted, from the last")
      ->capture_default_str();
  cmd->add_option("--steps", c->options.steps, "Full-batch AdamW steps per fold")
      ->capture_default_str();
  cmd->add_option("--lr", c->options.lr, "Learning rate")->capture_default_str();
  cmd->add_option("--folds", c->options.folds, "Grouped folds (at most)")->capture_default_str();
  cmd->add_option("-s,--seed", c->options.seed, "Seed (folds, bootstrap, torch)")
      ->capture_default_str();
  cmd->add_option("-t,--threads", c->options.threads, "Torch threads")->capture_default_str();
  cmd->footer(kExitCodeFooter);
  cmd->callback([c, &exit_code] { exit_code = run_adapt(*c); });
}

}  // namespace tlvlink::cli
