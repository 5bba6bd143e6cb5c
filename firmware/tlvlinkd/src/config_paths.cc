// check_config_paths: the files a configuration names are of the kind the daemon will open
// (config.h). Opened non-blocking, so a FIFO answers at once instead of hanging the check.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "tlvlink/daemon/config.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::daemon {
namespace {

// A file read at start: a regular file (a FIFO would block the daemon before it takes signals).
Status readable_file(const std::string& path, const char* key) {
  auto f = RegularFile::open(path.c_str());
  if (!f.ok())
    return Error(ErrorCode::kInvalidArgument, f.error().message()).with_context("%s", key);
  return Status();
}

}  // namespace

Status check_jsonl_target(const std::string& path) {
  if (path == "-") return Status();  // stdout: whatever the caller connected (a pipe is fine)
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    TLV_ENSURE(errno == ENOENT, ErrorCode::kInvalidArgument, "output jsonl:%s: %s", path.c_str(),
               std::strerror(errno));
    return Status();  // created at start
  }
  // A FIFO would block open() until a reader comes and write() whenever it stops reading, past
  // SIGTERM; a reader of live records pipes `jsonl:-` instead.
  TLV_ENSURE(S_ISREG(st.st_mode) || S_ISCHR(st.st_mode), ErrorCode::kInvalidArgument,
             "output jsonl:%s: not a regular file or character device (%s); for a pipe use "
             "jsonl:- and the shell",
             path.c_str(), file_type_name(st.st_mode));
  return Status();
}

Status check_config_paths(const DaemonConfig& c) {
  if (!c.model_public_key.empty()) TLV_TRY(readable_file(c.model_public_key, "model_public_key"));
  if (!c.command_script.empty()) TLV_TRY(readable_file(c.command_script, "command_script"));
  for (const std::string& o : c.outputs) {
    if (o.rfind("jsonl:", 0) == 0) TLV_TRY(check_jsonl_target(o.substr(6)));
  }
  for (const SensorConfig& s : c.sensors) {
    if (s.source != SourceKind::kReplay) continue;
    if (Status st = readable_file(s.device, "device"); !st.ok()) {
      return st.error().with_context("sensor '%s'", s.name.c_str());
    }
  }
  return Status();
}

}  // namespace tlvlink::daemon
