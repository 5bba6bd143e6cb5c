// `tlvlink stability MODEL`: the same touch through every image path (JPEG, the sensors' live
// decode; real frames re-encoded and shifted), and how far embeddings and heads move.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "common.h"
#include "tlvlink/eval/stability.h"
#include "tlvlink/io/file.h"

namespace tlvlink::cli {
namespace {

struct StabilityFlags {
  std::string model, json;
  eval::StabilityOptions o;
  ExecutorFlags exec;
  bool check = false, overwrite = false;
};

int run_stability(StabilityFlags& f) {
  if (!f.json.empty() && !f.overwrite && std::filesystem::exists(f.json)) {
    std::fprintf(stderr, "tlvlink stability: %s exists (pass --overwrite to replace it)\n",
                 f.json.c_str());
    return kExitUsage;
  }
  auto model = load_model(f.model);
  if (!model.ok()) return report_error("stability", model.error());
  f.o.embedder.executor = f.exec.kind();
  f.o.embedder.threads = f.exec.threads;
  auto r = eval::measure_stability(**model, f.o);
  if (!r.ok()) return report_error("stability", r.error());
  std::fputs(eval::format_stability(*r).c_str(), stdout);
  if (!f.json.empty()) {
    const std::string text = eval::stability_json(*r) + "\n";
    const Status st =
        tools::write_file(f.json, std::as_bytes(std::span<const char>(text.data(), text.size())));
    if (!st.ok()) return report_error("stability", st.error());
  }
  if (f.check && !r->meets_target()) {
    std::fprintf(stderr, "tlvlink stability: below the targets (--check)\n");
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace

void add_stability_command(CLI::App& app, int& exit_code) {
  auto f = std::make_shared<StabilityFlags>();
  CLI::App* cmd = app.add_subcommand(
      "stability",
      "Embedding stability: simulated touches (unseen sensor instances, GelSight Mini and DIGIT) "
      "as rendered vs saved as JPEG q95/q90/q75 vs through the sensor's live decode, and real "
      "frames (--real DIR) re-encoded and shifted by 3 DN; cosine min/p5/median and each head's "
      "agreement per path");
  cmd->add_option("model", f->model, "Model file (.tlvm)")->required();
  cmd->add_option("--scenes", f->o.scenes, "Simulated scenes (one press each)")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  cmd->add_option("--seed", f->o.seed, "Simulator seed of the scenes")->capture_default_str();
  cmd->add_option("--sensors", f->o.sensors, "Sensor profiles, comma-separated")
      ->capture_default_str();
  cmd->add_option("--real", f->o.real_frames_dir,
                  "A folder of real frames (PNG/JPEG, searched recursively); a missing folder is "
                  "reported and skipped");
  cmd->add_option("--json", f->json, "Also write the report as JSON to this file");
  cmd->add_flag("--overwrite", f->overwrite, "Replace an existing --json file");
  cmd->add_flag("--check", f->check, "Exit 1 when a path misses the targets");
  f->exec.add_to(*cmd);
  cmd->footer(kExitCodeFooter);
  cmd->callback([f, &exit_code] { exit_code = run_stability(*f); });
}

}  // namespace tlvlink::cli
