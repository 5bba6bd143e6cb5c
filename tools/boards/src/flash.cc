#include "tlvlink/boards/flash.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>

namespace tlvlink::boards {
namespace {

uint64_t size_of(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 ? static_cast<uint64_t>(st.st_size) : 0;
}

std::string absolute(const std::string& p) {
  if (!p.empty() && p[0] == '/') return p;
  char* cwd = ::getcwd(nullptr, 0);
  std::string out = std::string(cwd != nullptr ? cwd : ".") + "/" + p;
  std::free(cwd);
  return out;
}

// Configure + build tlvlinkd for the board with the scene's options (logs beside the build).
Status build_daemon(const FlashOptions& o, const Board& b, const BuildPlan& plan,
                    const std::string& dir) {
  std::string configure =
      "cmake -S " + shell_quote(o.source_dir) + " --preset " + b.name + " -B " + shell_quote(dir);
  for (const BuildOption& opt : plan.options) configure += " -D" + opt.name + "=" + opt.value;
  Status s = run_command(configure + " >" + shell_quote(dir + ".configure.log") + " 2>&1");
  if (!s.ok())
    return s.error().with_context("configuring %s (log: %s.configure.log)", b.name.c_str(),
                                  dir.c_str());
  s = run_command("cmake --build " + shell_quote(dir) + " -j " + std::to_string(o.jobs) +
                  " --target tlvlinkd >" + shell_quote(dir + ".build.log") + " 2>&1");
  if (!s.ok())
    return s.error().with_context("building tlvlinkd for %s (log: %s.build.log)", b.name.c_str(),
                                  dir.c_str());
  return {};
}

// A cache variable of an existing build tree ("" when the tree or the variable is not there).
std::string cache_value(const std::string& dir, const char* name) {
  auto line = command_output("sed -n 's/^" + std::string(name) + ":[A-Z]*=//p' " +
                             shell_quote(dir + "/CMakeCache.txt") + " 2>/dev/null");
  std::string value = line.ok() ? *line : "";
  while (!value.empty() && (value.back() == '\n' || value.back() == '\r')) value.pop_back();
  return value;
}

// One tree per compiler target (-mcpu), shared by the boards and scenes built for it: another
// board with the same -mcpu, or another scene, rebuilds only what its options change.
std::string default_build_dir(const FlashOptions& o, const Board& b) {
  const std::string cpu = b.option("TLVLINK_TARGET_CPU");
  return o.out_dir + "/" + (cpu.empty() ? b.name : cpu) + "-build";
}

// An existing tree configured for another -mcpu is refused: reusing its objects would put one
// CPU's code into another board's package.
Status check_tree_cpu(const std::string& dir, const Board& b) {
  const std::string cpu = cache_value(dir, "TLVLINK_TARGET_CPU");
  if (cpu.empty()) return {};  // a new tree, or one without a target CPU
  TLV_ENSURE(cpu == b.option("TLVLINK_TARGET_CPU"), ErrorCode::kInvalidArgument,
             "build tree %s is configured for -mcpu=%s; board '%s' needs -mcpu=%s (use another "
             "--build-dir)",
             dir.c_str(), cpu.c_str(), b.name.c_str(), b.option("TLVLINK_TARGET_CPU").c_str());
  return {};
}

// make_sysroot.sh's stamp, from the build's TLVLINK_SYSROOT (arm64 package versions).
std::string sysroot_stamp(const std::string& build_dir) {
  const std::string dir = cache_value(build_dir, "TLVLINK_SYSROOT");
  return dir.empty() ? "" : dir + "/.tlvlink-sysroot-stamp";
}

// The emulated board boots the package's own files: the staged root copied into the rig's
// initramfs, with the start-up script standing in for dpkg's postinst and systemd.
Status write_emulated_image(const std::string& source, const std::string& root,
                            const std::string& dir) {
  const std::string cmd = "python3 " + shell_quote(source + "/tools/rig/rig.py") +
                          " image --rootfs " + shell_quote(root) + " --script " +
                          shell_quote(source + "/firmware/package/qemu-virt-boot.sh") + " --out " +
                          shell_quote(dir) + " >" + shell_quote(dir + ".log") + " 2>&1";
  TLV_TRY(run_command("mkdir -p " + shell_quote(dir)));
  Status s = run_command(cmd);
  if (!s.ok()) return s.error().with_context("emulated board image (log: %s.log)", dir.c_str());
  return {};
}

}  // namespace

Result<FlashReport> flash(const FlashOptions& o) {
  FlashReport r;
  TLV_ASSIGN_OR_RETURN(r.board, load_board(o.source_dir + "/boards", o.board));
  TLV_ASSIGN_OR_RETURN(r.scene, daemon::find_scene(o.source_dir + "/boards/scenes", o.scene));
  TLV_ASSIGN_OR_RETURN(r.plan, plan_build(r.board, r.scene));
  const std::string work = absolute(o.out_dir + "/" + r.board.name + "-" + r.scene.name);
  TLV_TRY(run_command("mkdir -p " + shell_quote(work)));

  // The model first: a scene that does not fit the model fails before a long build.
  const std::string model = work + "/" + r.scene.name + ".tlvm";
  const std::string source_model =
      o.model.empty() ? o.source_dir + "/firmware/models/touch-tiny-int8.tlvm" : o.model;
  TLV_ASSIGN_OR_RETURN(r.strip, strip_model(source_model, r.scene, model, o.sign_key));

  const std::string build =
      absolute(o.build_dir.empty() ? default_build_dir(o, r.board) : o.build_dir);
  TLV_TRY(check_tree_cpu(build, r.board));
  TLV_TRY(build_daemon(o, r.board, r.plan, build));
  r.build_dir = build;
  const std::string daemon = build + "/firmware/tlvlinkd/tlvlinkd";
  TLV_ENSURE(size_of(daemon) > 0, ErrorCode::kIo, "%s: no tlvlinkd in the build", daemon.c_str());

  PackageInput in;
  in.board = r.board;
  in.scene = r.scene;
  in.source_dir = absolute(o.source_dir);
  in.daemon_binary = daemon;
  in.model_path = model;
  in.sysroot_stamp = r.board.arch == "arm64" ? sysroot_stamp(build) : "";
  if (!o.install_to.empty()) {
    TLV_ASSIGN_OR_RETURN(r.files, stage_root(in, o.install_to));
    // Enable the services as `systemctl enable` would (the board's first boot starts them;
    // systemd-sysusers makes the user from /usr/lib/sysusers.d/tlvlink.conf).
    const std::string wants = o.install_to + "/etc/systemd/system/multi-user.target.wants";
    TLV_TRY(run_command("mkdir -p " + shell_quote(wants)));
    for (const std::string& u : package_units(r.scene))
      TLV_TRY(run_command("ln -sf /lib/systemd/system/" + u + " " + shell_quote(wants + "/" + u)));
    r.artefact = o.install_to;
  } else {
    TLV_ASSIGN_OR_RETURN(r.artefact, build_deb(in, work, work));
    r.artefact_bytes = size_of(r.artefact);
    TLV_ASSIGN_OR_RETURN(r.files, stage_root(in, work + "/root"));
    if (r.board.emulated) {
      r.image_dir = work + "/image";
      TLV_TRY(write_emulated_image(in.source_dir, work + "/root", r.image_dir));
    }
  }
  for (const StagedFile& f : r.files)
    if (f.path == "/usr/bin/tlvlinkd") r.daemon_bytes = f.bytes;
  return r;
}

}  // namespace tlvlink::boards
