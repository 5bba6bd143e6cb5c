#pragma once
// `tlvlink flash --board NAME [--scene S] [-o DIR] [--install-to ROOTFS]`: build tlvlinkd for
// the board without what the scene does not use (build_options.h), strip the model to the
// scene's heads (strip.h), and make the board package (package.h) or write its files into a
// root filesystem. The emulated board (qemu-virt-a76) gets the same package; its initramfs is
// not assembled here yet.

#include <string>
#include <vector>

#include "tlvlink/boards/build_options.h"
#include "tlvlink/boards/package.h"
#include "tlvlink/boards/strip.h"

namespace tlvlink::boards {

struct FlashOptions {
  std::string board;
  std::string scene = "grasp-two-mini";
  std::string source_dir = ".";     // the repository: boards/, firmware/, runtime/
  std::string model = "firmware/models/touch-tiny-int8.tlvm";  // relative to source_dir
  std::string out_dir = "build/flash";  // DIR/<board>-<scene>/ gets the build, model and .deb
  std::string install_to;           // non-empty: write the files into this root instead
  std::string build_dir;            // non-empty: an existing build of the board to reuse
  int jobs = 2;
};

struct FlashReport {
  Board board;
  daemon::Scene scene;
  BuildPlan plan;
  StripReport strip;
  std::string artefact;             // the .deb, or the root filesystem written
  uint64_t artefact_bytes = 0, daemon_bytes = 0;
  std::vector<StagedFile> files;
};

Result<FlashReport> flash(const FlashOptions& options);

}  // namespace tlvlink::boards
