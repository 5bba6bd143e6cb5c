// tlvlinkd --config FILE [--check]: the board daemon (firmware/tlvlinkd/README.md).
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>

#include "tlvlink/daemon/config.h"
#include "tlvlink/daemon/session.h"

namespace {

void usage(std::FILE* out) {
  std::fprintf(out,
               "usage: tlvlinkd --config FILE [--check]\n"
               "  --config FILE  the TOML configuration (firmware/tlvlinkd/tlvlinkd.toml)\n"
               "  --check        validate the configuration and exit\n"
               "Signals: SIGTERM/SIGINT stop (computed predictions are flushed), SIGHUP reloads.\n"
               "Exit codes: 0 stopped cleanly, 1 runtime error (model, camera), 2 configuration "
               "error.\n");
}

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) on the JSON-lines output then fails the write with EFBIG, an
  // output error the daemon counts, instead of killing it with computed predictions unsent.
  std::signal(SIGXFSZ, SIG_IGN);
  std::string config;
  bool check = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--config") == 0 && i + 1 < argc) {
      config = argv[++i];
    } else if (std::strcmp(argv[i], "--check") == 0) {
      check = true;
    } else if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      usage(stdout);
      return 0;
    } else {
      std::fprintf(stderr, "tlvlinkd: unknown argument '%s'\n", argv[i]);
      usage(stderr);
      return tlvlink::daemon::kExitConfig;
    }
  }
  if (config.empty()) {
    usage(stderr);
    return tlvlink::daemon::kExitConfig;
  }
  if (check) {
    auto c = tlvlink::daemon::load_config(config);
    if (!c.ok()) {
      std::fprintf(stderr, "tlvlinkd: %s\n", c.error().message());
      return tlvlink::daemon::kExitConfig;
    }
    std::printf("%s: valid (%zu sensor(s), model %s)\n", config.c_str(), c->sensors.size(),
                c->model.c_str());
    return 0;
  }
  return tlvlink::daemon::run_daemon(config);
}
