// `tlvlink train`, `export` and `adapt` in a build without the trainer (TLVLINK_BUILD_TRAINER=OFF):
// the commands exist so their absence is explained instead of being unknown subcommands.

#include <cstdio>

#include "common.h"

namespace tlvlink::cli {
namespace {

void add_unavailable(CLI::App& app, int& exit_code, const char* name, const char* what) {
  CLI::App* cmd =
      app.add_subcommand(name, std::string(what) + " (not built: TLVLINK_BUILD_TRAINER=OFF)");
  cmd->allow_extras();
  cmd->footer(kExitCodeFooter);
  cmd->callback([&exit_code, name] {
    std::fprintf(stderr,
                 "tlvlink %s: this tlvlink was built with TLVLINK_BUILD_TRAINER=OFF; install "
                 "libtorch-dev (tools/setup/install_deps.sh test) and reconfigure with "
                 "-DTLVLINK_BUILD_TRAINER=ON (the host preset does)\n",
                 name);
    exit_code = kExitFailure;
  });
}

}  // namespace

void add_train_command(CLI::App& app, int& exit_code) {
  add_unavailable(app, exit_code, "train", "Train an edge touch encoder with TLV-Link");
}

void add_adapt_command(CLI::App& app, int& exit_code) {
  add_unavailable(app, exit_code, "adapt",
                  "Compare an encoder adapted on your frames with a linear head");
}

void add_export_command(CLI::App& app, int& exit_code) {
  add_unavailable(app, exit_code, "export", "Export a training checkpoint to .tlvm");
}

}  // namespace tlvlink::cli
