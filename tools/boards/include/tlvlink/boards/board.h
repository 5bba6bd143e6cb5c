#pragma once
// A board definition (boards/<name>.json): the CMake preset `board-<name>` with its cache
// variables (merged with the presets it inherits) and the deployment facts it keeps as preset
// vendor data under "tlvlink/board" (CPU, Debian architecture, the /proc/cpuinfo features the
// build needs, XNNPACK's kernel family, default threads, CPU affinity).

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::boards {

struct Board {
  std::string name;  // "rpi5-a76": the preset `name`, file boards/<name>.json
  std::string display_name, description;
  std::map<std::string, std::string> cache;  // cacheVariables, inherited ones included
  bool cross = false;                        // a toolchain file (aarch64) is set
  std::string cpu, arch;  // "4x Cortex-A76 @ 2.4 GHz", Debian architecture ("arm64")
  std::vector<std::string> cpu_features;  // /proc/cpuinfo "Features" the build needs
                                          // (cache variable TLVLINK_TARGET_FEATURES)
  std::string xnnpack_kernels;
  int32_t threads = 1;       // encoder threads in the scene's daemon configuration
  std::string cpu_affinity;  // systemd CPUAffinity= for tlvlinkd ("" = any CPU)
  bool emulated = false;     // the emulated board (tools/rig): flash also writes kernel + initramfs

  std::string option(const std::string& key) const;  // a cache variable, "" when unset
};

// Reads boards_dir/<name>.json. Errors: an unknown board (listing the known ones), a file that
// is not a board definition, a missing vendor field.
Result<Board> load_board(const std::string& boards_dir, const std::string& name);
// The boards that carry deployment facts (vendor data), sorted.
std::vector<std::string> board_names(const std::string& boards_dir);

}  // namespace tlvlink::boards
