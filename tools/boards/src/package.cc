#include "tlvlink/boards/package.h"

#include <sys/stat.h>

#include <array>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <sstream>

#include "tlvlink/daemon/scene.h"

namespace tlvlink::boards {
namespace {

Result<std::string> read_text(const std::string& path) {
  std::ifstream in(path);
  TLV_ENSURE(in.good(), ErrorCode::kIo, "%s: cannot open", path.c_str());
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

Status write_text(const std::string& path, const std::string& text, mode_t mode) {
  TLV_TRY(run_command("mkdir -p " + shell_quote(path.substr(0, path.find_last_of('/')))));
  std::ofstream out(path, std::ios::trunc);
  TLV_ENSURE(out.good(), ErrorCode::kIo, "%s: cannot write", path.c_str());
  out << text;
  out.close();
  TLV_ENSURE(out.good() && ::chmod(path.c_str(), mode) == 0, ErrorCode::kIo, "%s: write failed",
             path.c_str());
  return {};
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
  return s;
}

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string out;
  for (const std::string& s : v) out += (out.empty() ? "" : sep) + s;
  return out;
}

}  // namespace

std::string fill_template(std::string t, const PackageInput& in) {
  std::vector<std::string> units = package_units(in.scene), reversed(units.rbegin(), units.rend());
  char date[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%a, %d %b %Y %H:%M:%S +0000", std::gmtime(&now));
  t = replace_all(t, "@BOARD@", in.board.name);
  t = replace_all(t, "@SCENE@", in.scene.name);
  t = replace_all(t, "@CPU@", in.board.cpu);
  t = replace_all(t, "@MCPU@",
                  in.board.option("TLVLINK_TARGET_CPU").empty()
                      ? "default"
                      : in.board.option("TLVLINK_TARGET_CPU"));
  t = replace_all(t, "@CPU_FEATURES@", join(in.board.cpu_features, " "));
  t = replace_all(t, "@UNITS@", join(units, " "));
  t = replace_all(t, "@UNITS_REVERSED@", join(reversed, " "));
  t = replace_all(t, "@VERSION@", in.version);
  t = replace_all(t, "@DATE@", date);
  return t;
}

namespace {

// The systemd unit with the board's CPU affinity (RK3588: the A76 cluster).
std::string unit_text(std::string unit, const PackageInput& in) {
  if (!in.board.cpu_affinity.empty()) {
    unit = replace_all(
        unit, "Restart=on-failure\n",
        "Restart=on-failure\n# " + in.board.name +
            ": the encoder threads on the big cores.\nCPUAffinity=" + in.board.cpu_affinity + "\n");
  }
  return replace_all(unit, "file:///usr/share/doc/tlvlink/README.md", "man:tlvlinkd(8)");
}

struct SonamePackage {
  const char* soname;
  const char* package;
  const char* min_version;  // "" = from the sysroot stamp / dpkg-query
};
// Debian 12's packages for every library tlvlinkd may load (checked with dpkg-deb -c on the
// arm64 .debs make_sysroot.sh downloads). libc6 / libstdc++6 / libgcc-s1: Debian 12's
// toolchain (glibc 2.36, GCC 12) builds against them.
constexpr std::array<SonamePackage, 14> kSonames{{
    {"libXNNPACK.so.0", "libxnnpack0", ""},
    {"libpthreadpool.so.0", "libpthreadpool0", ""},
    {"libcpuinfo.so.0", "libcpuinfo0", ""},
    {"libturbojpeg.so.0", "libturbojpeg0", ""},
    {"libjpeg.so.62", "libjpeg62-turbo", ""},
    {"libusb-1.0.so.0", "libusb-1.0-0", ""},
    {"libsodium.so.23", "libsodium23", ""},
    {"libudev.so.1", "libudev1", ""},
    {"libcamera.so.0.0", "libcamera0.0.3", ""},
    {"libcamera-base.so.0.0", "libcamera0.0.3", ""},
    {"libstdc++.so.6", "libstdc++6", "12"},
    {"libgcc_s.so.1", "libgcc-s1", "3.0"},
    {"libc.so.6", "libc6", "2.36"},
    {"libm.so.6", "libc6", "2.36"},
}};

}  // namespace

std::string shell_quote(const std::string& s) { return "'" + replace_all(s, "'", "'\\''") + "'"; }

Status run_command(const std::string& command) {
  const int rc = std::system(command.c_str());
  TLV_ENSURE(rc == 0, ErrorCode::kIo, "command failed (status %d): %s", rc, command.c_str());
  return {};
}

Result<std::string> command_output(const std::string& command) {
  std::FILE* p = ::popen(command.c_str(), "r");
  TLV_ENSURE(p != nullptr, ErrorCode::kIo, "cannot run: %s", command.c_str());
  std::string out;
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
  const int rc = ::pclose(p);
  TLV_ENSURE(rc == 0, ErrorCode::kIo, "command failed (status %d): %s", rc, command.c_str());
  return out;
}

std::string installed_model_path(const PackageInput& in) {
  return "/usr/share/tlvlink/models/" + in.scene.name + ".tlvm";
}

std::vector<std::string> package_units(const daemon::Scene& scene) {
  std::vector<std::string> units;
  if (daemon::scene_needs(scene).usb) units.push_back("tlvlink-usb-gadget.service");
  units.push_back("tlvlinkd.service");
  if (daemon::scene_needs(scene).usb) units.push_back("tlvlink-usb-bind.service");
  return units;
}

Result<std::vector<StagedFile>> stage_root(const PackageInput& in, const std::string& root) {
  const std::string pkg = in.source_dir + "/firmware/package/";
  const std::string daemon = in.source_dir + "/firmware/tlvlinkd/";
  std::vector<StagedFile> files;
  const auto add = [&](const std::string& dest, const std::string& text, mode_t mode) -> Status {
    TLV_TRY(write_text(root + dest, text, mode));
    files.push_back({dest, text.size()});
    return {};
  };
  // The daemon, stripped (lintian: no debug symbols in a binary package).
  const std::string strip = in.board.arch == "arm64" ? "aarch64-linux-gnu-strip" : "strip";
  TLV_TRY(run_command("mkdir -p " + shell_quote(root + "/usr/bin") + " && " + strip +
                      " --strip-unneeded -o " + shell_quote(root + "/usr/bin/tlvlinkd") + " " +
                      shell_quote(in.daemon_binary) + " && chmod 0755 " +
                      shell_quote(root + "/usr/bin/tlvlinkd")));
  struct stat st {};
  ::stat((root + "/usr/bin/tlvlinkd").c_str(), &st);
  files.push_back({"/usr/bin/tlvlinkd", static_cast<uint64_t>(st.st_size)});
  TLV_ASSIGN_OR_RETURN(const std::string model, read_text(in.model_path));
  TLV_TRY(add(installed_model_path(in), model, 0644));
  TLV_TRY(add("/etc/tlvlink/tlvlinkd.toml",
              daemon::scene_config_toml(in.scene, installed_model_path(in), in.board.threads,
                                        "board " + in.board.name + ", made by tlvlink flash"),
              0644));
  TLV_ASSIGN_OR_RETURN(const std::string unit, read_text(daemon + "tlvlinkd.service"));
  TLV_TRY(add("/lib/systemd/system/tlvlinkd.service", unit_text(unit, in), 0644));
  TLV_ASSIGN_OR_RETURN(const std::string rules, read_text(daemon + "60-tlvlink.rules"));
  TLV_TRY(add("/lib/udev/rules.d/60-tlvlink.rules", rules, 0644));
  TLV_TRY(add("/usr/lib/sysusers.d/tlvlink.conf",
              "# The system user tlvlinkd runs as (systemd-sysusers; the package's postinst\n"
              "# makes it with adduser).\nu tlvlink - \"tlvlink daemon\" /var/lib/tlvlink\n"
              "m tlvlink video\nm tlvlink dialout\n",
              0644));
  if (daemon::scene_needs(in.scene).usb) {
    TLV_ASSIGN_OR_RETURN(const std::string gadget,
                         read_text(in.source_dir + "/runtime/transport/scripts/usb_gadget.sh"));
    TLV_TRY(add("/usr/libexec/tlvlink/usb_gadget.sh", gadget, 0755));
    for (const char* u : {"tlvlink-usb-gadget.service", "tlvlink-usb-bind.service"}) {
      TLV_ASSIGN_OR_RETURN(const std::string text, read_text(pkg + u));
      TLV_TRY(add(std::string("/lib/systemd/system/") + u, text, 0644));
    }
  }
  const std::string doc = "/usr/share/doc/tlvlink/";
  TLV_ASSIGN_OR_RETURN(const std::string copyright, read_text(pkg + "copyright"));
  TLV_TRY(add(doc + "copyright", copyright, 0644));
  TLV_ASSIGN_OR_RETURN(const std::string reference, read_text(daemon + "tlvlinkd.toml"));
  TLV_TRY(add(doc + "tlvlinkd.toml", reference, 0644));
  TLV_ASSIGN_OR_RETURN(const std::string changelog, read_text(pkg + "changelog"));
  TLV_TRY(write_text(root + doc + "changelog", fill_template(changelog, in), 0644));
  TLV_TRY(run_command("gzip -9nf " + shell_quote(root + doc + "changelog")));
  files.push_back({doc + "changelog.gz", 0});
  TLV_ASSIGN_OR_RETURN(const std::string man, read_text(pkg + "tlvlinkd.8"));
  TLV_TRY(write_text(root + "/usr/share/man/man8/tlvlinkd.8", man, 0644));
  TLV_TRY(run_command("gzip -9nf " + shell_quote(root + "/usr/share/man/man8/tlvlinkd.8")));
  files.push_back({"/usr/share/man/man8/tlvlinkd.8.gz", 0});
  return files;
}

Result<std::string> package_depends(const PackageInput& in, const std::string& binary) {
  TLV_ASSIGN_OR_RETURN(const std::string dynamic,
                       command_output("readelf -d " + shell_quote(binary)));
  std::map<std::string, std::string> versions;  // package -> version (stamp: "pkg:arm64=ver")
  if (!in.sysroot_stamp.empty()) {
    auto stamp = read_text(in.sysroot_stamp);
    std::istringstream lines(stamp.ok() ? *stamp : "");
    for (std::string l; std::getline(lines, l);) {
      const size_t eq = l.find('='), colon = l.find(':');
      if (eq != std::string::npos) versions[l.substr(0, std::min(colon, eq))] = l.substr(eq + 1);
    }
  }
  std::vector<std::string> deps = {"adduser"};
  std::istringstream lines(dynamic);
  for (std::string l; std::getline(lines, l);) {
    const size_t a = l.find("(NEEDED)"), lb = l.find('['), rb = l.find(']');
    if (a == std::string::npos || lb == std::string::npos || rb == std::string::npos) continue;
    const std::string soname = l.substr(lb + 1, rb - lb - 1);
    const SonamePackage* found = nullptr;
    for (const SonamePackage& s : kSonames)
      if (soname == s.soname) found = &s;
    if (found == nullptr && soname.rfind("ld-linux", 0) == 0) continue;  // libc6's loader
    TLV_ENSURE(found != nullptr, ErrorCode::kInvalidState,
               "%s needs %s, which no Debian package in tools/boards/src/package.cc's table "
               "provides: add it there",
               binary.c_str(), soname.c_str());
    std::string version = found->min_version;
    if (version.empty() && versions.count(found->package)) version = versions[found->package];
    if (version.empty() && in.board.arch == "amd64") {
      auto v = command_output(std::string("dpkg-query -W -f='${Version}' ") + found->package);
      if (v.ok()) version = *v;
    }
    const std::string dep =
        std::string(found->package) + (version.empty() ? "" : " (>= " + version + ")");
    bool seen = false;
    for (const std::string& d : deps)
      seen = seen || d.rfind(std::string(found->package) + " ", 0) == 0 || d == found->package;
    if (!seen) deps.push_back(dep);
  }
  return join(deps, ", ");
}

Result<std::string> build_deb(const PackageInput& in, const std::string& work_dir,
                              const std::string& out_dir) {
  const std::string root = work_dir + "/root";
  TLV_TRY(run_command("rm -rf " + shell_quote(root) + " && mkdir -p " +
                      shell_quote(root + "/DEBIAN") + " " + shell_quote(out_dir)));
  TLV_TRY(stage_root(in, root).status());
  TLV_ASSIGN_OR_RETURN(const std::string depends, package_depends(in, in.daemon_binary));
  TLV_ASSIGN_OR_RETURN(const std::string du,
                       command_output("du -sk --exclude=DEBIAN " + shell_quote(root)));
  const std::string pkg = in.source_dir + "/firmware/package/";
  std::string control;
  control += "Package: tlvlink\nVersion: " + in.version + "\nArchitecture: " + in.board.arch + "\n";
  control += "Maintainer: tlvlink maintainers <tlvlink@example.invalid>\n";
  control += "Installed-Size: " + du.substr(0, du.find_first_of(" \t")) + "\n";
  control += "Depends: " + depends + "\nSection: misc\nPriority: optional\n";
  control += "Description: tactile sensor inference daemon for " + in.board.name + "\n";
  control +=
      " tlvlinkd turns the frames of GelSight-type tactile sensors into predictions\n"
      " (int8 touch encoder on XNNPACK) and streams them over a serial or USB link\n"
      " or as JSON lines.\n .\n Board: " +
      in.board.name + "\n CPU: " + in.board.cpu + "\n Scene: " + in.scene.name +
      "\n .\n It refuses to install on a CPU without the features the build needs.\n";
  TLV_TRY(write_text(root + "/DEBIAN/control", control, 0644));
  TLV_TRY(write_text(root + "/DEBIAN/conffiles", "/etc/tlvlink/tlvlinkd.toml\n", 0644));
  for (const char* script : {"preinst", "postinst", "prerm", "postrm"}) {
    TLV_ASSIGN_OR_RETURN(const std::string text, read_text(pkg + script));
    TLV_TRY(write_text(root + "/DEBIAN/" + script, fill_template(text, in), 0755));
  }
  TLV_TRY(run_command("cd " + shell_quote(root) +
                      " && find . -path ./DEBIAN -prune -o -path ./etc -prune -o -type f -print"
                      " | sed 's|^\\./||' | LC_ALL=C sort | xargs md5sum > DEBIAN/md5sums"));
  const std::string deb = out_dir + "/tlvlink_" + in.version + "_" + in.board.arch + ".deb";
  TLV_TRY(run_command("dpkg-deb --root-owner-group -Zxz --build " + shell_quote(root) + " " +
                      shell_quote(deb) + " >/dev/null"));
  return deb;
}

}  // namespace tlvlink::boards
