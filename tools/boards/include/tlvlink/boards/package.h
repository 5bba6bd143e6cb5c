#pragma once
// The board package: the files a board gets (tlvlinkd, the stripped model, the scene's daemon
// configuration, the systemd units, udev rules, the USB gadget script, a sysusers entry, docs)
// laid out as a root filesystem tree, and the Debian package made from that tree with
// dpkg-deb (maintainer scripts from firmware/package/: a CPU check before unpacking, the
// system user and `tlvlinkd --verify` at configure time). `--install-to ROOTFS` writes the same
// tree into a mounted root filesystem.

#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/boards/board.h"
#include "tlvlink/daemon/scene.h"
#include "tlvlink/error.h"

namespace tlvlink::boards {

struct PackageInput {
  Board board;
  daemon::Scene scene;
  std::string source_dir;     // the repository (firmware/package, firmware/tlvlinkd, runtime/...)
  std::string daemon_binary;  // the board's tlvlinkd
  std::string model_path;     // the stripped model
  std::string sysroot_stamp;  // make_sysroot.sh's stamp (arm64 package versions); "" on amd64
  std::string version = "0.1.0";
};

struct StagedFile {
  std::string path;  // absolute on the board, e.g. /usr/bin/tlvlinkd
  uint64_t bytes = 0;
};

// Installed model path and the units the scene's package enables.
std::string installed_model_path(const PackageInput& in);
std::vector<std::string> package_units(const daemon::Scene& scene);

// A firmware/package/ template with its @NAME@ placeholders filled for this board and scene
// (@BOARD@, @CPU@, @MCPU@, @CPU_FEATURES@, @UNITS@, @UNITS_REVERSED@, @SCENE@, @VERSION@, @DATE@).
std::string fill_template(std::string text, const PackageInput& in);

// Writes the board's files under `root` (created). The daemon binary is stripped.
Result<std::vector<StagedFile>> stage_root(const PackageInput& in, const std::string& root);

// The Depends line for `binary`: each NEEDED library mapped to its Debian package (an unknown
// library is an error naming it), versions from the sysroot stamp or dpkg-query, plus adduser.
Result<std::string> package_depends(const PackageInput& in, const std::string& binary);

// Stages into work_dir/root, adds DEBIAN/ (control, conffiles, md5sums, maintainer scripts) and
// runs dpkg-deb --build; returns the .deb's path (in out_dir).
Result<std::string> build_deb(const PackageInput& in, const std::string& work_dir,
                              const std::string& out_dir);

// Shell helpers shared by the library (a failing command is an error naming it).
Status run_command(const std::string& command);
Result<std::string> command_output(const std::string& command);
std::string shell_quote(const std::string& s);

}  // namespace tlvlink::boards
