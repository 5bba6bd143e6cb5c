#include "pty_cable.h"

#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <sys/eventfd.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <span>
#include <vector>

namespace tlvlink::testing {
namespace {

Result<int> open_pty(const std::string& link) {
  const int m = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  char path[128];
  if (m < 0 || grantpt(m) != 0 || unlockpt(m) != 0 || ptsname_r(m, path, sizeof(path)) != 0) {
    return Error::make(ErrorCode::kIo, "pty: %s", std::strerror(errno));
  }
  termios tio;
  tcgetattr(m, &tio);
  cfmakeraw(&tio);
  tcsetattr(m, TCSANOW, &tio);
  const int s = ::open(path, O_RDWR | O_NOCTTY);  // so that "no reader" shows as hangup
  if (s >= 0) ::close(s);
  const std::string tmp = link + ".new";
  ::unlink(tmp.c_str());
  if (::symlink(path, tmp.c_str()) != 0 || ::rename(tmp.c_str(), link.c_str()) != 0) {
    ::close(m);
    return Error::make(ErrorCode::kIo, "symlink %s: %s", link.c_str(), std::strerror(errno));
  }
  return m;
}

}  // namespace

PtyCable::PtyCable(std::string dir) : dir_(std::move(dir)) {}
PtyCable::PtyCable(std::string dir, Faults faults) : dir_(std::move(dir)), faults_(faults) {}

PtyCable::~PtyCable() { unplug(); }

Status PtyCable::plug() {
  unplug();
  TLV_ASSIGN_OR_RETURN(board_master_, open_pty(board_path()));
  TLV_ASSIGN_OR_RETURN(host_master_, open_pty(host_path()));
  stop_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  running_ = true;
  thread_ = std::thread([this] { relay(); });
  return Status();
}

void PtyCable::unplug() {
  if (running_.exchange(false)) {
    const uint64_t one = 1;
    (void)!::write(stop_fd_, &one, sizeof(one));
    thread_.join();
  }
  for (int* fd : {&board_master_, &host_master_, &stop_fd_}) {
    if (*fd >= 0) ::close(*fd);
    *fd = -1;
  }
  ::unlink(board_path().c_str());
  ::unlink(host_path().c_str());
}

PtyCable::Counts PtyCable::counts() const {
  std::lock_guard lock(mutex_);
  return counts_;
}

void PtyCable::relay() {
  ByteFaults faults(faults_);
  struct Direction {
    int from, to;
    bool faulty;
    std::vector<unsigned char> pending;
    size_t pos = 0;
  };
  Direction dirs[2] = {{board_master_, host_master_, true, {}, 0},
                       {host_master_, board_master_, false, {}, 0}};
  unsigned char buf[4096];
  while (running_) {
    pollfd fds[3] = {{board_master_, POLLIN, 0}, {host_master_, POLLIN, 0}, {stop_fd_, POLLIN, 0}};
    for (Direction& d : dirs) {
      pollfd& to = fds[d.to == board_master_ ? 0 : 1];
      if (d.pos < d.pending.size()) to.events |= POLLOUT;
    }
    if (::poll(fds, 3, 10) < 0 && errno != EINTR) return;
    if (fds[2].revents & POLLIN) return;
    bool progress = false;
    for (Direction& d : dirs) {
      if (d.pos == d.pending.size()) {
        d.pending.clear();
        d.pos = 0;
        const ssize_t n = ::read(d.from, buf, sizeof(buf));
        if (n > 0) {
          progress = true;
          const size_t at = d.pending.size();
          d.pending.resize(at + static_cast<size_t>(n));
          if (d.faulty) {
            const ByteFaultCounts before = faults.counts();
            const size_t kept = faults.apply(std::as_bytes(std::span(buf, static_cast<size_t>(n))),
                                             reinterpret_cast<std::byte*>(d.pending.data() + at));
            d.pending.resize(at + kept);
            std::lock_guard lock(mutex_);
            counts_.bytes += faults.counts().bytes - before.bytes;
            counts_.corrupted += faults.counts().corrupted - before.corrupted;
            counts_.dropped += faults.counts().dropped - before.dropped;
          } else {
            std::memcpy(d.pending.data() + at, buf, static_cast<size_t>(n));
          }
        }
      }
      if (d.pos < d.pending.size()) {
        // A reader-less end buffers in the kernel until full, then refuses: the back-pressure
        // a real link with an absent reader gives.
        const ssize_t n = ::write(d.to, d.pending.data() + d.pos, d.pending.size() - d.pos);
        if (n > 0) {
          d.pos += static_cast<size_t>(n);
          progress = true;
        }
      }
    }
    // Hung-up masters poll ready at once: do not spin while nothing moves.
    if (!progress) ::usleep(2000);
  }
}

}  // namespace tlvlink::testing
