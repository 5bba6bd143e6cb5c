// `tlvlink-train`: the libtorch half of the CLI (`train`, `export`, `adapt`). `tlvlink
// train|export|adapt ...` runs this program with the same arguments (tools/cli/train_forward.cc),
// so the main `tlvlink` binary does not load libtorch.

#include <CLI/CLI.hpp>

#include "common.h"

int main(int argc, char** argv) {
  using namespace tlvlink::cli;
  CLI::App app{"tlvlink train / export: TLV-Link training with libtorch and export to .tlvm"};
  app.name("tlvlink");
  app.footer(kExitCodeFooter);
  app.require_subcommand(1);
  int exit_code = kExitOk;
  add_train_command(app, exit_code);
  add_export_command(app, exit_code);
  add_adapt_command(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kExitUsage;
  }
  return exit_code;
}
