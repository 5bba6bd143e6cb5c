#include "support/cli_run.h"

#include <sys/wait.h>

#include <cstdio>

namespace tlvlink::testing {

CliRun run_cli(const std::string& binary, const std::string& args, Stderr stderr_mode,
               const std::string& emulator) {
  const std::string cmd = (emulator.empty() ? "" : emulator + " ") + binary + " " + args +
                          (stderr_mode == Stderr::kMerged ? " 2>&1" : " 2>/dev/null");
  CliRun r;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (p == nullptr) return r;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof(buf), p)) > 0) r.out.append(buf, n);
  const int status = ::pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace tlvlink::testing
