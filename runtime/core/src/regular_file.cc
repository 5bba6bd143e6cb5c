#include "tlvlink/regular_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace tlvlink {

const char* file_type_name(unsigned mode) {
  if (S_ISDIR(mode)) return "directory";
  if (S_ISFIFO(mode)) return "FIFO";
  if (S_ISCHR(mode)) return "character device";
  if (S_ISBLK(mode)) return "block device";
  if (S_ISSOCK(mode)) return "socket";
  return "special file";
}

Result<RegularFile> RegularFile::open(const char* path) {
  // O_NONBLOCK: opening a FIFO with no writer returns at once instead of waiting for one.
  const int fd = ::open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  TLV_ENSURE(fd >= 0, ErrorCode::kIo, "%s: cannot open: %s", path, std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int err = errno;
    ::close(fd);
    return Error::make(ErrorCode::kIo, "%s: cannot stat: %s", path, std::strerror(err));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    return Error::make(ErrorCode::kIo, "%s: not a regular file (%s)", path,
                       file_type_name(st.st_mode));
  }
  // Regular files never block; clearing the flag keeps reads plain for every filesystem.
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return RegularFile(fd, static_cast<uint64_t>(st.st_size));
}

RegularFile::RegularFile(RegularFile&& other) noexcept : fd_(other.fd_), size_(other.size_) {
  other.fd_ = -1;
}

RegularFile& RegularFile::operator=(RegularFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    size_ = other.size_;
    other.fd_ = -1;
  }
  return *this;
}

RegularFile::~RegularFile() {
  if (fd_ >= 0) ::close(fd_);
}

Status RegularFile::read_at(std::span<std::byte> dst, uint64_t offset, const char* path) const {
  size_t done = 0;
  while (done < dst.size()) {
    const ssize_t n =
        ::pread(fd_, dst.data() + done, dst.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    TLV_ENSURE(n >= 0, ErrorCode::kIo, "%s: read error: %s", path, std::strerror(errno));
    TLV_ENSURE(n > 0, ErrorCode::kIo, "%s: truncated while reading (%zu of %zu bytes at %llu)",
               path, done, dst.size(), static_cast<unsigned long long>(offset));
    done += static_cast<size_t>(n);
  }
  return {};
}

Result<size_t> RegularFile::read_some(std::span<std::byte> dst, const char* path) const {
  for (;;) {
    const ssize_t n = ::read(fd_, dst.data(), dst.size());
    if (n < 0 && errno == EINTR) continue;
    TLV_ENSURE(n >= 0, ErrorCode::kIo, "%s: read error: %s", path, std::strerror(errno));
    return static_cast<size_t>(n);
  }
}

Result<size_t> RegularFile::read_head(const char* path, std::span<std::byte> dst) {
  TLV_ASSIGN_OR_RETURN(const RegularFile f, open(path));
  size_t done = 0;
  while (done < dst.size()) {
    TLV_ASSIGN_OR_RETURN(const size_t n, f.read_some(dst.subspan(done), path));
    if (n == 0) break;
    done += n;
  }
  return done;
}

}  // namespace tlvlink
