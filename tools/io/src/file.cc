#include "tlvlink/io/file.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

namespace tlvlink::tools {
namespace {
struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;
}  // namespace

Result<std::vector<std::byte>> read_file(const std::string& path, size_t max_bytes) {
  File f(std::fopen(path.c_str(), "rb"));
  if (!f)
    return Error::make(ErrorCode::kIo, "%s: cannot open: %s", path.c_str(), std::strerror(errno));
  struct stat st {};
  if (fstat(fileno(f.get()), &st) != 0) {
    return Error::make(ErrorCode::kIo, "%s: cannot stat: %s", path.c_str(), std::strerror(errno));
  }
  TLV_ENSURE(!S_ISDIR(st.st_mode), ErrorCode::kIo, "%s: is a directory", path.c_str());
  // Regular files are checked before reading; pipes are read up to the limit + 1 byte.
  if (S_ISREG(st.st_mode)) {
    TLV_ENSURE(static_cast<unsigned long long>(st.st_size) <= max_bytes, ErrorCode::kFormat,
               "%s: file is %lld bytes, larger than the %zu-byte limit", path.c_str(),
               static_cast<long long>(st.st_size), max_bytes);
  }
  std::vector<std::byte> bytes;
  std::byte chunk[1 << 16];
  for (;;) {
    const size_t n = std::fread(chunk, 1, sizeof(chunk), f.get());
    TLV_ENSURE(bytes.size() + n <= max_bytes, ErrorCode::kFormat,
               "%s: file is larger than the %zu-byte limit", path.c_str(), max_bytes);
    bytes.insert(bytes.end(), chunk, chunk + n);
    if (n < sizeof(chunk)) break;
  }
  TLV_ENSURE(!std::ferror(f.get()), ErrorCode::kIo, "%s: read error: %s", path.c_str(),
             std::strerror(errno));
  return bytes;
}

Status write_file(const std::string& path, std::span<const std::byte> bytes) {
  File f(std::fopen(path.c_str(), "wb"));
  if (!f)
    return Error::make(ErrorCode::kIo, "%s: cannot create: %s", path.c_str(), std::strerror(errno));
  TLV_ENSURE(std::fwrite(bytes.data(), 1, bytes.size(), f.get()) == bytes.size(), ErrorCode::kIo,
             "%s: write failed: %s", path.c_str(), std::strerror(errno));
  TLV_ENSURE(std::fclose(f.release()) == 0, ErrorCode::kIo, "%s: close failed: %s", path.c_str(),
             std::strerror(errno));
  return {};
}

}  // namespace tlvlink::tools
