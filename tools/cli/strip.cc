// tlvlink strip MODEL --scene S -o OUT: the model with only the heads and golden pairs the scene
// uses (tools/boards strip.h), checked as the board will check it.

#include <cstdio>

#include "common.h"
#include "tlvlink/boards/strip.h"
#include "tlvlink/daemon/scene.h"

namespace tlvlink::cli {
namespace {

struct StripOptions {
  std::string model, scene, scenes_dir = "boards/scenes", out, key;
};

int run_strip(const StripOptions& o) {
  // A path (ends in .toml) or a scene name in --scenes-dir.
  const bool is_path = o.scene.size() > 5 && o.scene.compare(o.scene.size() - 5, 5, ".toml") == 0;
  auto scene = is_path ? daemon::load_scene(o.scene) : daemon::find_scene(o.scenes_dir, o.scene);
  if (!scene.ok()) return report_error("strip", scene.error());
  auto r = boards::strip_model(o.model, *scene, o.out, o.key);
  if (!r.ok()) return report_error("strip", r.error());
  std::string kept, removed;
  for (const std::string& h : r->kept) kept += (kept.empty() ? "" : ", ") + h;
  for (const std::string& h : r->removed) removed += (removed.empty() ? "" : ", ") + h;
  std::printf("%s -> %s (scene %s): %llu -> %llu bytes\n", o.model.c_str(), o.out.c_str(),
              scene->name.c_str(), static_cast<unsigned long long>(r->bytes_before),
              static_cast<unsigned long long>(r->bytes_after));
  std::printf("  heads kept: %s\n  heads removed: %s\n", kept.empty() ? "none" : kept.c_str(),
              removed.empty() ? "none" : removed.c_str());
  std::printf("  golden pairs: %zu of %zu kept, verified: PASS\n", r->golden_after,
              r->golden_before);
  if (r->signed_copy) {
    std::printf("  signed with %s\n", o.key.c_str());
  } else if (!r->source_key_id.empty()) {
    std::printf(
        "  warning: the source was signed (key %s); this copy is not: pass --key to sign "
        "it, or a daemon with model_public_key refuses it\n",
        r->source_key_id.c_str());
  }
  return kExitOk;
}

}  // namespace

void add_strip_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<StripOptions>();
  CLI::App* cmd = app.add_subcommand(
      "strip", "Write a model with only the heads and golden pairs a scene uses (boards/scenes)");
  cmd->add_option("model", o->model, "Model file (.tlvm)")->required();
  cmd->add_option("--scene", o->scene, "Scene name (in --scenes-dir) or a scene .toml file")
      ->required();
  cmd->add_option("--scenes-dir", o->scenes_dir, "Where scene names are looked up")
      ->capture_default_str();
  cmd->add_option("-o,--output", o->out, "The stripped model")->required();
  cmd->add_option("--key", o->key, "Secret key file (tlvlink keygen): sign the stripped copy");
  cmd->footer(kExitCodeFooter);
  cmd->callback([o, &exit_code] { exit_code = run_strip(*o); });
}

}  // namespace tlvlink::cli
