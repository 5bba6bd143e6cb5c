#include "tlvlink/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace tlvlink {
namespace {

// The directory part of `path` ("." when it has none) into `dir`.
void directory_of(const char* path, char* dir, size_t cap) {
  const char* slash = std::strrchr(path, '/');
  if (slash == nullptr) {
    std::snprintf(dir, cap, ".");
  } else if (slash == path) {
    std::snprintf(dir, cap, "/");
  } else {
    std::snprintf(dir, cap, "%.*s", static_cast<int>(slash - path), path);
  }
}

// The process umask without changing it: umask() can only be read by setting it, which would
// give other threads' files mode 0777 for a moment; Linux shows it in /proc/self/status.
mode_t current_umask() {
  if (std::FILE* f = std::fopen("/proc/self/status", "re")) {
    char line[128];
    unsigned mask = 0;
    bool found = false;
    while (!found && std::fgets(line, sizeof(line), f) != nullptr)
      found = std::sscanf(line, "Umask: %o", &mask) == 1;
    std::fclose(f);
    if (found) return static_cast<mode_t>(mask);
  }
  const mode_t mask = ::umask(022);  // no /proc: read it the racy way
  ::umask(mask);
  return mask;
}

// The mode the final file gets: the replaced file's, else what open(0666) would give.
mode_t target_mode(const char* path) {
  struct stat st {};
  if (::stat(path, &st) == 0 && S_ISREG(st.st_mode)) return st.st_mode & 07777;
  static const mode_t mask = current_umask();
  return 0666 & ~mask;
}

}  // namespace

const char* write_error_text(int err) {
  if (err == ENOSPC) return "disk full";
  if (err == EFBIG) return "file size limit reached";
  return std::strerror(err);
}

Result<AtomicFile> AtomicFile::create(const char* path) {
  AtomicFile f;
  const size_t len = std::strlen(path);
  TLV_ENSURE(len > 0 && len + 20 < kMaxPath, ErrorCode::kInvalidArgument,
             "output path of %zu characters (1..%zu)", len, kMaxPath - 20);
  TLV_ENSURE(path[len - 1] != '/', ErrorCode::kInvalidArgument, "%s: names a directory", path);
  std::memcpy(f.path_, path, len + 1);
  char dir[kMaxPath];
  directory_of(path, dir, sizeof(dir));
  const char* name = std::strrchr(path, '/') != nullptr ? std::strrchr(path, '/') + 1 : path;
  // Hidden and in the same directory: rename() is atomic only within one filesystem.
  const int n = std::snprintf(f.temp_, sizeof(f.temp_), "%s/.%s.tmp-XXXXXX", dir, name);
  TLV_ENSURE(n > 0 && static_cast<size_t>(n) < sizeof(f.temp_), ErrorCode::kInvalidArgument,
             "%s: path too long for a temporary beside it", path);
  f.fd_ = ::mkostemp(f.temp_, O_CLOEXEC);
  TLV_ENSURE(f.fd_ >= 0, ErrorCode::kIo, "%s: cannot create a temporary file in %s: %s", path, dir,
             write_error_text(errno));
  ::fchmod(f.fd_, target_mode(path));
  return f;
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept : fd_(other.fd_) {
  std::memcpy(path_, other.path_, sizeof(path_));
  std::memcpy(temp_, other.temp_, sizeof(temp_));
  other.fd_ = -1;
  other.temp_[0] = '\0';
}

AtomicFile& AtomicFile::operator=(AtomicFile&& other) noexcept {
  if (this != &other) {
    abandon();
    fd_ = other.fd_;
    std::memcpy(path_, other.path_, sizeof(path_));
    std::memcpy(temp_, other.temp_, sizeof(temp_));
    other.fd_ = -1;
    other.temp_[0] = '\0';
  }
  return *this;
}

AtomicFile::~AtomicFile() { abandon(); }

void AtomicFile::abandon() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (temp_[0] != '\0') ::unlink(temp_);
  temp_[0] = '\0';
}

Status AtomicFile::write(const void* data, size_t size) {
  TLV_ENSURE(fd_ >= 0, ErrorCode::kInvalidState, "%s: written after commit", path_);
  const auto* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd_, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : ENOSPC;
      abandon();
      return Error::make(ErrorCode::kIo, "%s: write failed: %s", path_, write_error_text(err));
    }
    p += n;
    size -= static_cast<size_t>(n);
  }
  return {};
}

Status AtomicFile::commit() {
  TLV_ENSURE(fd_ >= 0, ErrorCode::kInvalidState, "%s: committed twice or after a failure", path_);
  // fsync before rename: otherwise a crash can leave the new name pointing at empty blocks.
  if (::fsync(fd_) != 0 || ::close(fd_) != 0) {
    const int err = errno;
    fd_ = -1;
    abandon();
    return Error::make(ErrorCode::kIo, "%s: write failed: %s", path_, write_error_text(err));
  }
  fd_ = -1;
  if (::rename(temp_, path_) != 0) {
    const int err = errno;
    abandon();
    return Error::make(ErrorCode::kIo, "%s: cannot replace: %s", path_, std::strerror(err));
  }
  temp_[0] = '\0';
  // The rename itself is durable only once the directory is synced; best effort (some
  // filesystems refuse fsync on a directory), the file's bytes are already safe.
  char dir[kMaxPath];
  directory_of(path_, dir, sizeof(dir));
  const int dfd = ::open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
  return {};
}

Status write_file_atomic(const char* path, std::span<const std::byte> bytes) {
  TLV_ASSIGN_OR_RETURN(AtomicFile f, AtomicFile::create(path));
  TLV_TRY(f.write(bytes));
  return f.commit();
}

}  // namespace tlvlink
