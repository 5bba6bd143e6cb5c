#include "jsonl_writer.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "tlvlink/atomic_file.h"
#include "tlvlink/daemon/config.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::daemon::internal {
Result<JsonlWriter> JsonlWriter::open(const std::string& target) {
  JsonlWriter w;
  w.target_ = "jsonl:" + target;
  if (target == "-") {
    w.fd_ = STDOUT_FILENO;
    return w;
  }
  TLV_TRY(check_jsonl_target(target));
  // O_NONBLOCK: a FIFO put there since the check fails the open at once instead of waiting.
  w.fd_ = ::open(target.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | O_NONBLOCK, 0644);
  TLV_ENSURE(w.fd_ >= 0, ErrorCode::kIo, "output %s: %s", w.target_.c_str(), std::strerror(errno));
  w.owns_fd_ = true;
  struct stat st {};
  TLV_ENSURE(::fstat(w.fd_, &st) == 0 && (S_ISREG(st.st_mode) || S_ISCHR(st.st_mode)),
             ErrorCode::kInvalidArgument, "output %s: not a regular file or character device (%s)",
             w.target_.c_str(), file_type_name(st.st_mode));
  ::fcntl(w.fd_, F_SETFL, ::fcntl(w.fd_, F_GETFL) & ~O_NONBLOCK);
  return w;
}

JsonlWriter::JsonlWriter(JsonlWriter&& o) noexcept
    : fd_(std::exchange(o.fd_, -1)),
      owns_fd_(std::exchange(o.owns_fd_, false)),
      target_(std::move(o.target_)),
      lines_(o.lines_),
      failed_(o.failed_),
      too_long_(o.too_long_),
      last_errno_(o.last_errno_),
      closed_(o.closed_.load()) {}

JsonlWriter::~JsonlWriter() {
  if (owns_fd_ && fd_ >= 0) ::close(fd_);
}

void JsonlWriter::write_line() {
  if (closed_) return;  // the reader left: nobody to lose records to
  if (line_.overflowed()) {
    ++failed_;
    ++too_long_;
    return;
  }
  std::string_view v = line_.view();
  while (!v.empty()) {
    const ssize_t n = ::write(fd_, v.data(), v.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EPIPE) {  // SIGPIPE is ignored: the pipe's reader closed it
      closed_ = true;
      return;
    }
    if (n <= 0) {
      ++failed_;
      last_errno_ = n < 0 ? errno : EIO;
      return;
    }
    v.remove_prefix(static_cast<size_t>(n));
  }
  ++lines_;
}

std::string JsonlWriter::problem() const {
  std::string out;
  char text[256];
  if (closed_) {
    std::snprintf(text, sizeof text, "output %s: closed by its reader after %llu line(s)",
                  target_.c_str(), static_cast<unsigned long long>(lines_));
    out = text;
  }
  if (failed_ == 0) return out;
  std::snprintf(text, sizeof text, "%soutput %s: %llu record(s) not written (",
                out.empty() ? "" : "; ", target_.c_str(), static_cast<unsigned long long>(failed_));
  out += text;
  if (last_errno_ != 0) {
    std::snprintf(text, sizeof text, "%llu: %s",
                  static_cast<unsigned long long>(failed_ - too_long_),
                  write_error_text(last_errno_));
    out += text;
  }
  if (too_long_ != 0) {
    std::snprintf(text, sizeof text, "%s%llu: longer than the %zu-byte line buffer",
                  last_errno_ != 0 ? ", " : "", static_cast<unsigned long long>(too_long_),
                  kLineCapacity);
    out += text;
  }
  return out + ")";
}

}  // namespace tlvlink::daemon::internal
