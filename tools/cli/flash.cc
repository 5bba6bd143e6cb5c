// tlvlink flash --board NAME [--scene S] [-o DIR] [--install-to ROOTFS]: the board package
// (tools/boards flash.h): tlvlinkd built for the board without what the scene does not use,
// the stripped model, the scene's configuration, units, udev rules, gadget set-up.

#include <cstdio>

#include "common.h"
#include "tlvlink/boards/flash.h"

namespace tlvlink::cli {
namespace {

std::string human(uint64_t b) {
  char s[32];
  if (b >= 1048576)
    std::snprintf(s, sizeof s, "%.2f MB", static_cast<double>(b) / 1048576);
  else
    std::snprintf(s, sizeof s, "%.1f KB", static_cast<double>(b) / 1024);
  return s;
}

int run_flash(const boards::FlashOptions& o) {
  auto r = boards::flash(o);
  if (!r.ok()) return report_error("flash", r.error());
  std::printf("board %s (%s; XNNPACK %s), scene %s\n", r->board.name.c_str(), r->board.cpu.c_str(),
              r->board.xnnpack_kernels.c_str(), r->scene.name.c_str());
  std::printf("build tree: %s\n", r->build_dir.c_str());
  std::printf("built: %s (%s)\n", r->artefact.c_str(),
              r->artefact_bytes ? human(r->artefact_bytes).c_str() : "directory tree");
  std::printf("  tlvlinkd %s (stripped); model %s -> %s\n", human(r->daemon_bytes).c_str(),
              human(r->strip.bytes_before).c_str(), human(r->strip.bytes_after).c_str());
  for (const boards::StagedFile& f : r->files) std::printf("  %s\n", f.path.c_str());
  std::printf("left out:\n");
  for (const std::string& s : r->plan.left_out) std::printf("  %s\n", s.c_str());
  for (const std::string& h : r->strip.removed)
    std::printf("  head %s (not in the scene)\n", h.c_str());
  std::printf("kept without a build option:\n");
  for (const std::string& s : r->plan.built_in) std::printf("  %s\n", s.c_str());
  if (!r->image_dir.empty())
    std::printf(
        "emulated board: %s/{vmlinuz,initramfs.cpio,boot.sh} (the package's files; "
        "boot.sh runs tlvlinkd --verify and --check in the guest)\n",
        r->image_dir.c_str());
  if (!r->strip.source_key_id.empty() && !r->strip.signed_copy)
    std::printf(
        "warning: %s was signed (key %s); the stripped copy is not: pass --key to sign it, "
        "or a daemon with model_public_key refuses it\n",
        o.model.empty() ? "the shipped model" : o.model.c_str(), r->strip.source_key_id.c_str());
  if (!o.install_to.empty())
    std::printf(
        "note: the CPU check and `tlvlinkd --verify` run at package install only; on first "
        "boot run: tlvlinkd --config /etc/tlvlink/tlvlinkd.toml --verify\n");
  return kExitOk;
}

}  // namespace

void add_flash_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<boards::FlashOptions>();
  CLI::App* cmd = app.add_subcommand(
      "flash",
      "Build the Debian package (or a root filesystem tree) of tlvlinkd for a board and scene");
  cmd->add_option("--board", o->board, "Board (boards/<name>.json)")->required();
  cmd->add_option("--scene", o->scene, "Scene (boards/scenes/<name>.toml)")->capture_default_str();
  cmd->add_option("-o,--output", o->out_dir, "Output directory")->capture_default_str();
  cmd->add_option("--install-to", o->install_to,
                  "Write the files into this root filesystem instead");
  cmd->add_option("--model", o->model, "Model to strip (default: the shipped int8 model)");
  cmd->add_option("--key", o->sign_key,
                  "Secret key file (tlvlink keygen): sign the stripped model");
  cmd->add_option("--source", o->source_dir, "The tlvlink source tree")->capture_default_str();
  cmd->add_option("--build-dir", o->build_dir,
                  "Build tree (default: OUTPUT/<mcpu>-build; configured with the board and scene, "
                  "built incrementally)");
  cmd->add_option("-j,--jobs", o->jobs, "Build jobs")->capture_default_str();
  cmd->footer(kExitCodeFooter);
  cmd->callback([o, &exit_code] { exit_code = run_flash(*o); });
}

}  // namespace tlvlink::cli
