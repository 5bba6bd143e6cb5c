#include "tlvlink/listen/recording.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

#include "tlvlink/atomic_file.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::listen {
namespace {

int64_t clock_ns(clockid_t id) {
  timespec ts;
  clock_gettime(id, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void put64(std::byte* p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = std::byte((v >> (8 * i)) & 0xFF);
}
uint64_t get64(const std::byte* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<uint64_t>(p[i]) << (8 * i);
  return v;
}

}  // namespace

Result<std::FILE*> create_recording_file(const std::string& path, bool overwrite,
                                         const char* what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    return Error::make(ErrorCode::kIo, "%s %s: not a regular file (%s)", what, path.c_str(),
                       file_type_name(st.st_mode));
  }
  // O_NONBLOCK: a FIFO put there since the stat fails at once (ENXIO) instead of blocking the
  // open, or is refused below. O_EXCL unless told to replace what is there.
  const int fd = ::open(
      path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | O_NONBLOCK | (overwrite ? 0 : O_EXCL), 0644);
  TLV_ENSURE(fd >= 0 || errno != EEXIST, ErrorCode::kInvalidArgument,
             "%s %s already exists (give --overwrite to replace it)", what, path.c_str());
  TLV_ENSURE(fd >= 0, ErrorCode::kIo, "creating %s %s: %s", what, path.c_str(),
             std::strerror(errno));
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return Error::make(ErrorCode::kIo, "%s %s: not a regular file (%s)", what, path.c_str(),
                       file_type_name(st.st_mode));
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  if (overwrite && ::ftruncate(fd, 0) != 0) {
    const int err = errno;
    ::close(fd);
    return Error::make(ErrorCode::kIo, "%s %s: %s", what, path.c_str(), std::strerror(err));
  }
  std::FILE* f = ::fdopen(fd, "wb");
  if (f == nullptr) ::close(fd);
  TLV_ENSURE(f != nullptr, ErrorCode::kIo, "creating %s %s: %s", what, path.c_str(),
             std::strerror(errno));
  return f;
}

// File header: magic[8] version:u16 header_size:u16 reserved:u32 start_wall_ns:i64
// start_mono_ns:i64. Record: time_ns:i64 length:u32 kind:u8 reserved[3] data[length]. All
// little-endian.
Result<std::unique_ptr<RecordingWriter>> RecordingWriter::create(const std::string& path,
                                                                 bool overwrite) {
  TLV_ASSIGN_OR_RETURN(std::FILE * f, create_recording_file(path, overwrite));
  std::byte header[kRecordingHeaderSize] = {};
  std::memcpy(header, kRecordingMagic, 8);
  header[8] = std::byte{kRecordingVersion & 0xFF};
  header[9] = std::byte{kRecordingVersion >> 8};
  header[10] = std::byte{kRecordingHeaderSize};
  put64(header + 16, static_cast<uint64_t>(clock_ns(CLOCK_REALTIME)));
  put64(header + 24, static_cast<uint64_t>(clock_ns(CLOCK_MONOTONIC)));
  if (std::fwrite(header, 1, sizeof(header), f) != sizeof(header) || std::fflush(f) != 0) {
    const int err = errno;
    std::fclose(f);
    return Error::make(ErrorCode::kIo, "writing recording %s: %s", path.c_str(),
                       write_error_text(err));
  }
  return std::unique_ptr<RecordingWriter>(new RecordingWriter(f, path));
}

RecordingWriter::~RecordingWriter() {
  if (file_) std::fclose(file_);
}

Status RecordingWriter::write(RecordKind kind, int64_t time_ns, std::span<const std::byte> data) {
  TLV_ENSURE(data.size() <= kMaxRecordLength, ErrorCode::kInvalidArgument, "record of %zu bytes",
             data.size());
  std::byte head[kRecordHeaderSize] = {};
  put64(head, static_cast<uint64_t>(time_ns));
  const uint32_t n = static_cast<uint32_t>(data.size());
  for (int i = 0; i < 4; ++i) head[8 + i] = std::byte((n >> (8 * i)) & 0xFF);
  head[12] = static_cast<std::byte>(kind);
  TLV_ENSURE(std::fwrite(head, 1, sizeof(head), file_) == sizeof(head) &&
                 (data.empty() || std::fwrite(data.data(), 1, data.size(), file_) == data.size()),
             ErrorCode::kIo, "writing recording %s: %s", path_.c_str(), write_error_text(errno));
  return Status();
}

Status RecordingWriter::flush() {
  TLV_ENSURE(std::fflush(file_) == 0, ErrorCode::kIo, "writing recording %s: %s", path_.c_str(),
             write_error_text(errno));
  return Status();
}

Result<std::unique_ptr<RecordingReader>> RecordingReader::open(const std::string& path) {
  // A regular file only, opened non-blocking (a FIFO would hang the open past SIGTERM).
  auto regular = RegularFile::open(path.c_str());
  if (!regular.ok()) return regular.error().with_context("opening recording");
  const int fd = ::dup(regular->fd());
  std::FILE* f = fd >= 0 ? ::fdopen(fd, "rb") : nullptr;
  if (f == nullptr && fd >= 0) ::close(fd);
  TLV_ENSURE(f != nullptr, ErrorCode::kIo, "opening recording %s: %s", path.c_str(),
             std::strerror(errno));
  std::unique_ptr<RecordingReader> r(new RecordingReader(f, path));
  std::byte header[kRecordingHeaderSize];
  TLV_ENSURE(std::fread(header, 1, sizeof(header), f) == sizeof(header) &&
                 std::memcmp(header, kRecordingMagic, 8) == 0,
             ErrorCode::kFormat, "%s is not a tlvlink recording (no TLVLREC header)", path.c_str());
  const unsigned version = static_cast<unsigned>(header[8]) | static_cast<unsigned>(header[9]) << 8;
  const unsigned header_size = static_cast<unsigned>(header[10]) | static_cast<unsigned>(header[11])
                                                                       << 8;
  TLV_ENSURE(version == kRecordingVersion, ErrorCode::kFormat,
             "%s: recording format version %u; this build reads version %u", path.c_str(), version,
             kRecordingVersion);
  TLV_ENSURE(header_size >= kRecordingHeaderSize &&
                 std::fseek(f, static_cast<long>(header_size), SEEK_SET) == 0,
             ErrorCode::kFormat, "%s: bad header size %u", path.c_str(), header_size);
  r->start_wall_ns_ = static_cast<int64_t>(get64(header + 16));
  r->start_mono_ns_ = static_cast<int64_t>(get64(header + 24));
  return r;
}

RecordingReader::~RecordingReader() {
  if (file_) std::fclose(file_);
}

Result<bool> RecordingReader::next(Record& record) {
  std::byte head[kRecordHeaderSize];
  const size_t got = std::fread(head, 1, sizeof(head), file_);
  if (got == 0) return false;
  if (got < sizeof(head)) {
    truncated_ = true;
    return false;
  }
  const uint32_t n = static_cast<uint32_t>(head[8]) | static_cast<uint32_t>(head[9]) << 8 |
                     static_cast<uint32_t>(head[10]) << 16 | static_cast<uint32_t>(head[11]) << 24;
  TLV_ENSURE(n <= kMaxRecordLength, ErrorCode::kFormat, "%s: record of %u bytes (at most %zu)",
             path_.c_str(), n, kMaxRecordLength);
  record.time_ns = static_cast<int64_t>(get64(head));
  record.kind = static_cast<RecordKind>(head[12]);
  record.data.resize(n);
  if (n > 0 && std::fread(record.data.data(), 1, n, file_) != n) {
    truncated_ = true;
    return false;
  }
  return true;
}

}  // namespace tlvlink::listen
