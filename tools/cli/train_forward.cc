// `tlvlink train` and `tlvlink export` in a build with the trainer: they run the sibling
// executable `tlvlink-train` (same directory) with the same arguments. libtorch is linked only
// there: linking it into `tlvlink` costs ~2 s of dynamic loading on every command (measured:
// `tlvlink inspect` 2.2 s with libtorch linked, 0.06 s without, on this shared 2-core machine).

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "common.h"

namespace tlvlink::cli {
namespace {

std::string trainer_path() {
  char self[4096];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof(self) - 1);
  if (n <= 0) return "tlvlink-train";
  std::string dir(self, static_cast<size_t>(n));
  const size_t slash = dir.rfind('/');
  return (slash == std::string::npos ? std::string(".") : dir.substr(0, slash)) + "/tlvlink-train";
}

void add_forward(CLI::App& app, int& exit_code, const char* name, const char* help) {
  CLI::App* cmd = app.add_subcommand(name, help);
  cmd->prefix_command();  // every later argument goes to tlvlink-train untouched ...
  cmd->set_help_flag();   // ... --help included
  cmd->footer(kExitCodeFooter);
  cmd->callback([cmd, &exit_code, name] {
    const std::string exe = trainer_path();
    std::vector<std::string> args = {exe, name};
    for (const std::string& a : cmd->remaining()) args.push_back(a);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::fflush(stdout);
    ::execv(exe.c_str(), argv.data());
    std::fprintf(stderr,
                 "tlvlink %s: cannot run %s (%s); build it with `cmake --build BUILD --target "
                 "tlvlink-train` (TLVLINK_BUILD_TRAINER=ON)\n",
                 name, exe.c_str(), std::strerror(errno));
    exit_code = kExitFailure;
  });
}

}  // namespace

void add_train_command(CLI::App& app, int& exit_code) {
  add_forward(app, exit_code, "train",
              "Train an edge touch encoder with TLV-Link (vision teacher, curriculum, InfoNCE "
              "against frozen text features) on a Touch100k-format set [runs tlvlink-train]");
}

void add_adapt_command(CLI::App& app, int& exit_code) {
  add_forward(app, exit_code, "adapt",
              "Does adapting the encoder's last layer(s) to your labelled frames beat a linear "
              "head? Both on the same grouped folds [runs tlvlink-train]");
}

void add_export_command(CLI::App& app, int& exit_code) {
  add_forward(app, exit_code, "export",
              "Export a `tlvlink train` checkpoint to a float .tlvm (BatchNorm folded, input "
              "spec, zero-shot heads, provenance) [runs tlvlink-train]");
}

}  // namespace tlvlink::cli
