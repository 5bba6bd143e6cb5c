#pragma once
// Opening a file to read only when it is a regular file. Models, images and dataset members are
// untrusted paths: a FIFO would block open() or read() forever, a directory or a device
// (/dev/zero) would be read without end. open() never blocks (O_NONBLOCK), then fstat decides.

#include <cstddef>
#include <cstdint>
#include <span>

#include "tlvlink/error.h"

namespace tlvlink {

class RegularFile {
 public:
  // kIo "PATH: cannot open: why" or "PATH: not a regular file (FIFO)" (directory, character
  // device, block device, socket).
  static Result<RegularFile> open(const char* path);

  RegularFile(RegularFile&& other) noexcept;
  RegularFile& operator=(RegularFile&& other) noexcept;
  RegularFile(const RegularFile&) = delete;
  RegularFile& operator=(const RegularFile&) = delete;
  ~RegularFile();

  int fd() const { return fd_; }
  uint64_t size() const { return size_; }  // from fstat at open

  // Reads exactly dst.size() bytes at `offset`; a file that shrank since open is kIo naming
  // `path` ("truncated while reading").
  Status read_at(std::span<std::byte> dst, uint64_t offset, const char* path) const;
  // Up to dst.size() bytes from the current position; 0 at the end of the file.
  Result<size_t> read_some(std::span<std::byte> dst, const char* path) const;
  // Opens `path` as open() does and reads up to dst.size() bytes from its start (small files:
  // key files); returns how many. Errors as open() and read_some().
  static Result<size_t> read_head(const char* path, std::span<std::byte> dst);

 private:
  RegularFile(int fd, uint64_t size) : fd_(fd), size_(size) {}
  int fd_ = -1;
  uint64_t size_ = 0;
};

// "FIFO", "directory", "character device", ... for an st_mode that is not a regular file.
const char* file_type_name(unsigned mode);

}  // namespace tlvlink
