// A pty whose master is the transport; readers open the slave (or its symlink).
#include "tlvlink/transport/pty.h"

#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "fd_util.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::transport {
namespace {
// While nobody has the slave open the master polls as hung up at once: look again this often.
constexpr int kAbsentPollMs = 20;
}  // namespace

Status check_pty_link(const std::string& link) {
  if (link.empty()) return Status();
  struct stat st {};
  if (::lstat(link.c_str(), &st) != 0) {
    TLV_ENSURE(errno == ENOENT, ErrorCode::kInvalidArgument, "pty link %s: %s", link.c_str(),
               std::strerror(errno));
    return Status();
  }
  // Only a link to a pty slave is one a daemon made (maybe a run that was killed): anything else
  // is somebody's file, which replacing would destroy.
  char target[128];
  const ssize_t n = S_ISLNK(st.st_mode) ? ::readlink(link.c_str(), target, sizeof(target) - 1) : -1;
  TLV_ENSURE(n > 0 && std::string_view(target, static_cast<size_t>(n)).rfind("/dev/pts/", 0) == 0,
             ErrorCode::kInvalidArgument,
             "pty link %s already exists and is not a symlink to a /dev/pts slave (%s): "
             "refusing to replace it; remove it or choose another path",
             link.c_str(),
             S_ISLNK(st.st_mode)   ? "a symlink elsewhere"
             : S_ISREG(st.st_mode) ? "a regular file"
                                   : file_type_name(st.st_mode));
  return Status();
}

PtyTransport::PtyTransport(PtyConfig config)
    : config_(std::move(config)), wake_(internal::make_wake_fd()) {
  name_ = "pty";
  if (!config_.link.empty()) name_ += ":" + config_.link;
}

PtyTransport::~PtyTransport() {
  close();
  internal::close_fd(wake_);
}

Status PtyTransport::open() {
  close();
  TLV_TRY(check_pty_link(config_.link));
  const int m = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (m < 0) return Error::make(ErrorCode::kTransport, "posix_openpt: %s", std::strerror(errno));
  char path[128];
  if (grantpt(m) != 0 || unlockpt(m) != 0 || ptsname_r(m, path, sizeof(path)) != 0) {
    const int err = errno;
    ::close(m);
    return Error::make(ErrorCode::kTransport, "setting up a pty: %s", std::strerror(err));
  }
  // Raw mode for the pair (set through the master, it applies to the slave's line discipline).
  termios tio;
  if (tcgetattr(m, &tio) == 0) {
    cfmakeraw(&tio);
    tcsetattr(m, TCSANOW, &tio);
  }
  // Open and close the slave once: from then on the master reports hangup exactly while no
  // reader has the slave open (a never-opened slave does not).
  const int s = ::open(path, O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (s >= 0) ::close(s);
  if (!config_.link.empty()) {
    const std::string tmp = config_.link + ".new";
    ::unlink(tmp.c_str());
    if (::symlink(path, tmp.c_str()) != 0 || ::rename(tmp.c_str(), config_.link.c_str()) != 0) {
      const int err = errno;
      ::close(m);
      return Error::make(ErrorCode::kTransport, "pointing %s at %s: %s", config_.link.c_str(), path,
                         std::strerror(err));
    }
  }
  master_ = m;
  slave_path_ = path;
  name_ = "pty:" + slave_path_ + (config_.link.empty() ? "" : " (link " + config_.link + ")");
  peer_present_ = false;
  return Status();
}

void PtyTransport::close() {
  if (master_ < 0) return;
  internal::close_fd(master_);
  if (!config_.link.empty()) {
    // Remove the link only if it still points at this pty (a newer one may have replaced it).
    char target[128];
    const ssize_t n = ::readlink(config_.link.c_str(), target, sizeof(target) - 1);
    if (n > 0 && slave_path_ == std::string(target, static_cast<size_t>(n)))
      ::unlink(config_.link.c_str());
  }
  slave_path_.clear();
  peer_present_ = false;
}

Result<Readiness> PtyTransport::wait(bool want_write, int timeout_ms) {
  TLV_ENSURE(master_ >= 0, ErrorCode::kInvalidState, "%s: wait() on a closed link", name_.c_str());
  const short events = static_cast<short>(POLLIN | (want_write ? POLLOUT : 0));
  TLV_ASSIGN_OR_RETURN(short revents, internal::poll_with_wake(master_, events, wake_, 0));
  if (revents & POLLHUP) {
    peer_present_ = false;
    // Nobody reads: wait for the reader (or a wake-up) a little at a time.
    TLV_ASSIGN_OR_RETURN(
        revents, internal::poll_with_wake(-1, 0, wake_, std::min(timeout_ms, kAbsentPollMs)));
    return Readiness{};
  }
  peer_present_ = true;
  if ((revents & events) == 0) {
    TLV_ASSIGN_OR_RETURN(revents, internal::poll_with_wake(master_, events, wake_, timeout_ms));
    if (revents & POLLHUP) {
      peer_present_ = false;
      return Readiness{};
    }
  }
  if (revents & (POLLERR | POLLNVAL)) {
    return Error::make(ErrorCode::kTransportDisconnected, "%s: error on the master", name_.c_str());
  }
  return Readiness{(revents & POLLIN) != 0, (revents & POLLOUT) != 0};
}

Result<size_t> PtyTransport::read(std::span<std::byte> out) {
  const ssize_t n = ::read(master_, out.data(), out.size());
  if (n > 0) return static_cast<size_t>(n);
  if (n < 0 && errno == EIO) {  // no reader on the slave side
    peer_present_ = false;
    return size_t{0};
  }
  if (n == 0 || errno == EAGAIN || errno == EINTR) return size_t{0};
  return internal::io_error("read", name_, errno);
}

Result<size_t> PtyTransport::write(std::span<const std::byte> data) {
  const ssize_t n = ::write(master_, data.data(), data.size());
  if (n >= 0) return static_cast<size_t>(n);
  if (errno == EAGAIN || errno == EINTR) return size_t{0};
  if (errno == EIO) {
    peer_present_ = false;
    return size_t{0};
  }
  return internal::io_error("write", name_, errno);
}

void PtyTransport::interrupt() { internal::signal_wake_fd(wake_); }

// Closing the master discards what the reader has not read yet: wait for it. The reader's
// backlog is visible only from the slave side; TIOCGPTPEER opens it without a path, briefly.
// FIONREAD counts the line discipline's buffer, which the kernel refills from its flip buffers
// asynchronously: only empty looks for 100 ms in a row mean everything was read (20 ms lost a
// reader its last 4 predictions on a loaded 2-core machine, 2026-12-05: most likely that refill
// running late).
void PtyTransport::drain(int timeout_ms) {
  constexpr int kStepMs = 5, kEmptyLooks = 20;
  int empty = 0;
  for (int waited = 0; master_ >= 0 && peer_present_ && waited < timeout_ms && empty < kEmptyLooks;
       waited += kStepMs) {
    const int slave = ::ioctl(master_, TIOCGPTPEER, O_RDONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (slave < 0) return;
    int pending = 0;
    const int r = ::ioctl(slave, FIONREAD, &pending);
    ::close(slave);
    if (r != 0) return;
    empty = pending == 0 ? empty + 1 : 0;
    ::usleep(kStepMs * 1000);
  }
}

}  // namespace tlvlink::transport
