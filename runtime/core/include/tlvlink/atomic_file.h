#pragma once
// Replacing a file atomically: the bytes go to a temporary file in the target's directory,
// which is fsynced and then renamed over the target (and the directory fsynced). A failure at
// any step (disk full, file-size limit, a crash) leaves the previous file byte-identical, and
// the temporary is removed. Every file tlvlink writes goes through here (models, reports,
// dataset index files, recordings), so a failed write never destroys a good file.
//
//   TLV_ASSIGN_OR_RETURN(AtomicFile out, AtomicFile::create("model.tlvm"));
//   TLV_TRY(out.write(bytes.data(), bytes.size()));
//   TLV_TRY(out.commit());  // without commit, the destructor removes the temporary
//
// Errors are kIo and name the target path; ENOSPC reads "disk full", EFBIG "file size limit
// reached" (processes that write files ignore SIGXFSZ so the limit is an error, not a kill).

#include <cstddef>
#include <span>

#include "tlvlink/error.h"

namespace tlvlink {

class AtomicFile {
 public:
  static constexpr size_t kMaxPath = 4096;

  // Creates "<dir>/.<name>.tmp-XXXXXX" with the target's mode (0666 & ~umask when new).
  static Result<AtomicFile> create(const char* path);

  AtomicFile(AtomicFile&& other) noexcept;
  AtomicFile& operator=(AtomicFile&& other) noexcept;
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();  // abandon() unless committed

  Status write(const void* data, size_t size);  // all of it, or an error
  Status write(std::span<const std::byte> bytes) { return write(bytes.data(), bytes.size()); }
  // fsync, close, rename over the target, fsync the directory. Once; then the object is empty.
  Status commit();
  // Closes and removes the temporary; the target is untouched. Safe to call twice.
  void abandon();

  bool is_open() const { return fd_ >= 0; }
  // The temporary's descriptor, for writers that need pwrite/ftruncate (recordings).
  int fd() const { return fd_; }
  const char* path() const { return path_; }
  const char* temp_path() const { return temp_; }

 private:
  AtomicFile() = default;
  int fd_ = -1;
  char path_[kMaxPath] = {};
  char temp_[kMaxPath] = {};
};

// The whole of `bytes` as `path`, through an AtomicFile.
Status write_file_atomic(const char* path, std::span<const std::byte> bytes);

// "disk full" for ENOSPC, "file size limit reached" for EFBIG, strerror otherwise.
const char* write_error_text(int err);

}  // namespace tlvlink
