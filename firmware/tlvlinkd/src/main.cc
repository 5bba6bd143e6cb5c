// tlvlinkd --config FILE [--check | --verify]: the board daemon (firmware/tlvlinkd/README.md).
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>

#include "tlvlink/daemon/config.h"
#include "tlvlink/daemon/model_check.h"
#include "tlvlink/daemon/session.h"

namespace {

void usage(std::FILE* out) {
  std::fprintf(out,
               "usage: tlvlinkd --config FILE [--check | --verify]\n"
               "  --config FILE  the TOML configuration (firmware/tlvlinkd/tlvlinkd.toml)\n"
               "  --check        validate the configuration and exit\n"
               "  --verify       also load the model, run its golden pairs on the configured\n"
               "                 executor and check its heads and sensors (no camera opened);\n"
               "                 exit 1 on a mismatch (the board package runs it at install)\n"
               "Signals: SIGTERM/SIGINT stop (computed predictions are flushed), SIGHUP reloads.\n"
               "Exit codes: 0 stopped cleanly (or every output's reader left), 1 runtime error\n"
               "(model, camera, or an output that could not write records), 2 configuration "
               "error.\n");
}

// --verify: the model of the configuration on this board (tlvlink/daemon/model_check.h).
int verify_model(const tlvlink::daemon::DaemonConfig& c) {
  auto r = tlvlink::daemon::check_model(c);
  if (!r.ok()) {
    std::fprintf(stderr, "tlvlinkd: %s\n", r.error().message());
    return 1;
  }
  std::string heads;
  for (const std::string& h : r->reported_heads) heads += (heads.empty() ? "" : ", ") + h;
  std::printf(
      "%s: model '%s', %zu golden pair(s) on the %s executor: %s (max error %.4g, "
      "tolerance %.4g); heads: %s; grasp: %s\n",
      c.model.c_str(), r->model_name.c_str(), r->golden_pairs, c.executor.c_str(),
      r->golden_pass ? "PASS" : "FAIL", r->max_error, r->tolerance,
      heads.empty() ? "none" : heads.c_str(),
      r->grasp_head.empty() ? "off" : r->grasp_head.c_str());
  return r->golden_pass ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) on the JSON-lines output then fails the write with EFBIG, an
  // output error the daemon counts, instead of killing it with computed predictions unsent.
  std::signal(SIGXFSZ, SIG_IGN);
  // A closed pipe on `jsonl:-` (| head) is EPIPE, which closes that output: the daemon stops with
  // its summary instead of being killed without one.
  std::signal(SIGPIPE, SIG_IGN);
  std::string config;
  bool check = false, verify = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--config") == 0 && i + 1 < argc) {
      config = argv[++i];
    } else if (std::strcmp(argv[i], "--check") == 0) {
      check = true;
    } else if (std::strcmp(argv[i], "--verify") == 0) {
      verify = true;
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
  if (check || verify) {
    auto c = tlvlink::daemon::load_config(config);
    if (!c.ok()) {
      std::fprintf(stderr, "tlvlinkd: %s\n", c.error().message());
      return tlvlink::daemon::kExitConfig;
    }
    if (verify) return verify_model(*c);
    std::printf("%s: valid (%zu sensor(s), model %s)\n", config.c_str(), c->sensors.size(),
                c->model.c_str());
    return 0;
  }
  return tlvlink::daemon::run_daemon(config);
}
