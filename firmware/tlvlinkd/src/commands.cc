#include "commands.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace tlvlink::daemon::internal {

Result<std::vector<ScriptedCommand>> load_command_script(const std::string& path,
                                                         const int32_t sensor_of_finger[2]) {
  // Opened without blocking and checked to be a regular file: a FIFO here must not hang start.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  TLV_ENSURE(fd >= 0, ErrorCode::kIo, "command_script %s: %s", path.c_str(), std::strerror(errno));
  struct stat st_buf {};
  if (::fstat(fd, &st_buf) != 0 || !S_ISREG(st_buf.st_mode)) {
    ::close(fd);
    return Error::make(ErrorCode::kIo, "command_script %s: not a regular file", path.c_str());
  }
  std::FILE* f = ::fdopen(fd, "r");
  if (f == nullptr) {
    ::close(fd);
    return Error::make(ErrorCode::kIo, "command_script %s: %s", path.c_str(), std::strerror(errno));
  }
  std::vector<ScriptedCommand> out;
  char line[256];
  int64_t n = 0;
  Status st;
  while (st.ok() && std::fgets(line, sizeof line, f) != nullptr) {
    ++n;
    if (char* hash = std::strchr(line, '#')) *hash = '\0';
    char finger[8], command[16];
    unsigned long long sequence = 0;
    const int got = std::sscanf(line, "%7s %llu %15s", finger, &sequence, command);
    if (got <= 0) continue;  // blank or comment
    ScriptedCommand c;
    c.sequence = sequence;
    const std::string_view fg(finger), cmd(got == 3 ? command : "");
    const int32_t which = fg == "A" ? 0 : fg == "B" ? 1 : -1;
    if (got != 3 || which < 0 || (cmd != "closed" && cmd != "lifting")) {
      st = Error::make(ErrorCode::kFormat,
                       "%s:%lld: expected 'FINGER SEQUENCE COMMAND' (finger A or B, command "
                       "closed or lifting)",
                       path.c_str(), static_cast<long long>(n));
    } else if (sensor_of_finger[which] < 0) {
      st = Error::make(ErrorCode::kInvalidArgument, "%s:%lld: no sensor is finger %s", path.c_str(),
                       static_cast<long long>(n), finger);
    } else if (!out.empty() && sequence < out.back().sequence) {
      st = Error::make(ErrorCode::kFormat, "%s:%lld: sequence %llu before the previous line's %llu",
                       path.c_str(), static_cast<long long>(n), sequence,
                       static_cast<unsigned long long>(out.back().sequence));
    } else {
      c.sensor = sensor_of_finger[which];
      c.kind = cmd == "closed" ? CommandKind::kClosed : CommandKind::kLifting;
      out.push_back(c);
    }
  }
  std::fclose(f);
  if (!st.ok()) return st.error();
  return out;
}

bool CommandQueue::push(const Command& c) {
  std::lock_guard lock(mutex_);
  return ring_.try_push(c);
}

bool CommandQueue::pop(Command& out) {
  std::lock_guard lock(mutex_);
  return ring_.pop(out);
}

uint64_t CommandQueue::dropped() const {
  std::lock_guard lock(mutex_);
  return ring_.rejected();
}

}  // namespace tlvlink::daemon::internal
