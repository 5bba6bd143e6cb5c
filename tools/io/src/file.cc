#include "tlvlink/io/file.h"

#include "tlvlink/atomic_file.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::tools {

Result<std::vector<std::byte>> read_file(const std::string& path, size_t max_bytes) {
  TLV_ASSIGN_OR_RETURN(const RegularFile f, RegularFile::open(path.c_str()));
  TLV_ENSURE(f.size() <= max_bytes, ErrorCode::kFormat,
             "%s: file is %llu bytes, larger than the %zu-byte limit", path.c_str(),
             static_cast<unsigned long long>(f.size()), max_bytes);
  std::vector<std::byte> bytes(static_cast<size_t>(f.size()));
  TLV_TRY(f.read_at(bytes, 0, path.c_str()));
  return bytes;
}

Status write_file(const std::string& path, std::span<const std::byte> bytes) {
  return write_file_atomic(path.c_str(), bytes);
}

}  // namespace tlvlink::tools
