#pragma once
// `tlvlink flash --board NAME [--scene S] [-o DIR] [--install-to ROOTFS]`: build tlvlinkd for
// the board without what the scene does not use (build_options.h), strip the model to the
// scene's heads (strip.h), and make the board package (package.h) or write its files into a
// root filesystem. The emulated board (qemu-virt-a76) gets the same package, and a kernel +
// initramfs holding the package's files (tools/rig `rig.py image --rootfs`) with boot.sh.

#include <string>
#include <vector>

#include "tlvlink/boards/build_options.h"
#include "tlvlink/boards/package.h"
#include "tlvlink/boards/strip.h"

namespace tlvlink::boards {

struct FlashOptions {
  std::string board;
  std::string scene = "grasp-two-mini";
  std::string source_dir = ".";         // the repository: boards/, firmware/, runtime/
  std::string model;                    // "" = the shipped model (source_dir/firmware/models/...)
  std::string out_dir = "build/flash";  // DIR/<board>-<scene>/ gets the model, root and .deb
  std::string install_to;               // non-empty: write the files into this root instead
  std::string build_dir;                // the build tree (configured there with the board's preset
                                        // and the scene's options, built incrementally; one for
                                        // another -mcpu is refused); "" = DIR/<mcpu>-build
  std::string sign_key;  // a secret key file (`tlvlink keygen`): signs the stripped model
  int jobs = 2;
};

struct FlashReport {
  Board board;
  daemon::Scene scene;
  BuildPlan plan;
  StripReport strip;
  std::string artefact;   // the .deb, or the root filesystem written
  std::string build_dir;  // the tree tlvlinkd was built in
  std::string image_dir;  // emulated board: vmlinuz, initramfs.cpio, boot.sh
  uint64_t artefact_bytes = 0, daemon_bytes = 0;
  std::vector<StagedFile> files;
};

Result<FlashReport> flash(const FlashOptions& options);

}  // namespace tlvlink::boards
