// `tlvlink convert` in a build without the ONNX importer (TLVLINK_WITH_ONNX=OFF): the command
// exists so its absence is explained instead of being an unknown subcommand.

#include <cstdio>

#include "common.h"

namespace tlvlink::cli {

void add_convert_command(CLI::App& app, int& exit_code) {
  CLI::App* cmd = app.add_subcommand(
      "convert", "Convert an ONNX model to .tlvm (not built: TLVLINK_WITH_ONNX=OFF)");
  cmd->allow_extras();
  cmd->footer(kExitCodeFooter);
  cmd->callback([&exit_code] {
    std::fprintf(stderr,
                 "tlvlink convert: this tlvlink was built with TLVLINK_WITH_ONNX=OFF; install "
                 "libonnx-dev and libprotobuf-dev and reconfigure with -DTLVLINK_WITH_ONNX=ON\n");
    exit_code = kExitFailure;
  });
}

}  // namespace tlvlink::cli
