// run_daemon: sessions from the configuration until a stop signal, reloading on SIGHUP.
#include <poll.h>
#include <signal.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "clock.h"
#include "tlvlink/daemon/session.h"
#include "tlvlink/log.h"

namespace tlvlink::daemon {
namespace {

TLV_LOG_CATEGORY(kLogMain, "tlvlinkd");
constexpr int kPollMs = 100;

// SIGTERM, SIGINT and SIGHUP arrive through a signalfd; blocked in every thread (the threads the
// sessions start inherit the mask).
int signal_fd() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGHUP);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  return signalfd(-1, &set, SFD_CLOEXEC | SFD_NONBLOCK);
}

enum class Wake { kNothing, kStop, kReload };

// Waits up to kPollMs for a signal or a command line on stdin (when control = "stdin").
Wake wait(int sfd, bool stdin_commands, Session& session, bool& stdin_open) {
  pollfd fds[2] = {{sfd, POLLIN, 0}, {STDIN_FILENO, POLLIN, 0}};
  const nfds_t n = stdin_commands && stdin_open ? 2 : 1;
  if (poll(fds, n, kPollMs) <= 0) return Wake::kNothing;
  if ((fds[0].revents & POLLIN) != 0) {
    signalfd_siginfo info{};
    if (read(sfd, &info, sizeof info) == static_cast<ssize_t>(sizeof info)) {
      return info.ssi_signo == SIGHUP ? Wake::kReload : Wake::kStop;
    }
  }
  if (n == 2 && (fds[1].revents & (POLLIN | POLLHUP)) != 0) {
    char line[256];
    const ssize_t got = read(STDIN_FILENO, line, sizeof line - 1);
    if (got <= 0) {
      stdin_open = false;  // the controller closed its end: keep running without commands
      return Wake::kNothing;
    }
    line[got] = '\0';
    for (char *save = nullptr, *tok = strtok_r(line, "\n", &save); tok != nullptr;
         tok = strtok_r(nullptr, "\n", &save)) {
      if (!session.command(tok)) TLV_LOG(kLogMain, kWarning, "not a command: '%s'", tok);
    }
  }
  return Wake::kNothing;
}

}  // namespace

int run_daemon(const std::string& path) {
  auto config = load_config(path);
  if (!config.ok()) {
    std::fprintf(stderr, "tlvlinkd: %s\n", config.error().message());
    return kExitConfig;
  }
  const int sfd = signal_fd();
  if (sfd < 0) {
    std::fprintf(stderr, "tlvlinkd: signalfd: %s\n", std::strerror(errno));
    return kExitRuntime;
  }
  DaemonConfig current = std::move(config).value();
  uint64_t lost_records = 0, failed_sources = 0;
  for (;;) {
    auto session = Session::start(current);
    if (!session.ok()) {
      std::fprintf(stderr, "tlvlinkd: %s\n", session.error().message());
      close(sfd);
      return session.error().code() == ErrorCode::kInvalidArgument ? kExitConfig : kExitRuntime;
    }
    const int64_t started = board_clock_ns();
    bool stdin_open = true;
    Wake why = Wake::kNothing;
    while (why == Wake::kNothing) {
      why = wait(sfd, current.control == ControlInput::kStdin, **session, stdin_open);
      const bool timed_out =
          current.run_for_ms > 0 && board_clock_ns() - started >= current.run_for_ms * 1'000'000;
      if (why == Wake::kNothing && (timed_out || (*session)->limit_reached())) why = Wake::kStop;
      if (why == Wake::kReload) {
        auto reloaded = load_config(path);
        if (!reloaded.ok()) {
          TLV_LOG(kLogMain, kError, "SIGHUP: keeping the running configuration: %s",
                  reloaded.error().message());
          why = Wake::kNothing;
        } else {
          TLV_LOG(kLogMain, kInfo, "SIGHUP: %s reloaded; restarting the pipeline", path.c_str());
          current = std::move(reloaded).value();
        }
      }
    }
    const SessionTotals totals = (*session)->stop();
    // Records an output could not write were lost: the run did not do its job.
    lost_records += totals.write_errors;
    failed_sources += totals.failed_sources;
    if (why == Wake::kStop) break;
  }
  close(sfd);
  if (failed_sources > 0) {
    std::fprintf(stderr, "tlvlinkd: %llu replay source(s) stopped on an unusable recording\n",
                 static_cast<unsigned long long>(failed_sources));
  }
  if (lost_records > 0) {
    std::fprintf(stderr, "tlvlinkd: %llu record(s) not written to an output (see above)\n",
                 static_cast<unsigned long long>(lost_records));
  }
  return lost_records > 0 || failed_sources > 0 ? kExitRuntime : kExitOk;
}

}  // namespace tlvlink::daemon
