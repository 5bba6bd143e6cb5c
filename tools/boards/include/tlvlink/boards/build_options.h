#pragma once
// The build of one board for one scene: the board preset's options with the components the
// scene does not use switched off (cmake/options.cmake declares them), and what was left out.

#include <string>
#include <vector>

#include "tlvlink/boards/board.h"
#include "tlvlink/daemon/scene.h"

namespace tlvlink::boards {

struct BuildOption {
  std::string name, value;  // -D<name>=<value>
  std::string why;          // "scene outputs only JSON lines"
};

struct BuildPlan {
  std::vector<BuildOption> options;   // on top of the board preset
  std::vector<std::string> left_out;  // components not built, with the reason
  std::vector<std::string> built_in;  // scene-relevant parts that stay (not gated by an option)
};

// Always off for a package: tests, host tools, benchmarks, trainer, fuzzers. Then per scene:
// the stream protocol and transports (no stream link), USB (no usb output), libcamera (no
// libcamera source). An error when the scene needs what the board cannot build (a libcamera
// source on a board without libcamera in its sysroot).
Result<BuildPlan> plan_build(const Board& board, const daemon::Scene& scene);

}  // namespace tlvlink::boards
