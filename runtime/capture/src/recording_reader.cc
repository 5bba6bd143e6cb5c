// RecordingReader: a scan of the record headers at open, then pread() per frame.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

#include "recording_format.h"
#include "tlvlink/capture/recording.h"
#include "tlvlink/crc32.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::capture {
namespace {

// Reads exactly size bytes at offset; false at end of file.
Result<bool> pread_all(int fd, uint8_t* out, size_t size, uint64_t offset, const char* path) {
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::pread(fd, out + done, size - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    TLV_ENSURE(n >= 0, ErrorCode::kIo, "recording %s: read at offset %llu: %s", path,
               static_cast<unsigned long long>(offset + done), std::strerror(errno));
    if (n == 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

}  // namespace

Result<RecordingReader> RecordingReader::open(const std::string& path) {
  // O_NONBLOCK: a FIFO answers at once (and is refused below) instead of blocking the open.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  TLV_ENSURE(fd >= 0, ErrorCode::kIo, "recording %s: cannot open: %s", path.c_str(),
             std::strerror(errno));
  RecordingReader r;
  r.path_ = path;
  r.fd_ = fd;
  struct stat st {};
  TLV_ENSURE(::fstat(fd, &st) == 0, ErrorCode::kIo, "recording %s: cannot stat: %s", path.c_str(),
             std::strerror(errno));
  TLV_ENSURE(S_ISREG(st.st_mode), ErrorCode::kIo, "recording %s: not a regular file (%s)",
             path.c_str(), file_type_name(st.st_mode));
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  r.summary_.file_bytes = static_cast<uint64_t>(st.st_size);
  uint8_t header[kRecordingHeaderBytes];
  TLV_ASSIGN_OR_RETURN(const bool whole, pread_all(fd, header, sizeof(header), 0, path.c_str()));
  TLV_ENSURE(whole, ErrorCode::kFormat,
             "recording %s: %llu bytes, shorter than the %zu-byte header", path.c_str(),
             static_cast<unsigned long long>(r.summary_.file_bytes), kRecordingHeaderBytes);
  TLV_TRY(
      internal::decode_file_header(header, path.c_str(), r.summary_.format, r.summary_.version));
  TLV_TRY(r.scan());
  return r;
}

RecordingReader::RecordingReader(RecordingReader&& o) noexcept
    : path_(std::move(o.path_)), fd_(std::exchange(o.fd_, -1)), summary_(o.summary_) {}

RecordingReader& RecordingReader::operator=(RecordingReader&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(o.path_);
    fd_ = std::exchange(o.fd_, -1);
    summary_ = o.summary_;
  }
  return *this;
}

RecordingReader::~RecordingReader() {
  if (fd_ >= 0) ::close(fd_);
}

Result<bool> RecordingReader::parse_record(uint64_t offset, uint64_t index,
                                           int64_t previous_offset_ns, RecordInfo& out) const {
  uint8_t h[kRecordHeaderBytes];
  TLV_ASSIGN_OR_RETURN(const bool whole, pread_all(fd_, h, sizeof(h), offset, path_.c_str()));
  if (!whole) return false;  // end of file, or a header cut short (the scan counts it)
  internal::RecordFields f;
  const internal::RecordProblem problem = internal::decode_record_header(h, f);
  TLV_ENSURE(problem == internal::RecordProblem::kNone, ErrorCode::kFormat,
             "recording %s: record %llu at offset %llu: %s", path_.c_str(),
             static_cast<unsigned long long>(index), static_cast<unsigned long long>(offset),
             internal::record_problem_text(problem));
  TLV_ENSURE(f.offset_ns >= previous_offset_ns, ErrorCode::kFormat,
             "recording %s: record %llu at offset %llu is earlier (%lld ns) than the one before "
             "(%lld ns)",
             path_.c_str(), static_cast<unsigned long long>(index),
             static_cast<unsigned long long>(offset), static_cast<long long>(f.offset_ns),
             static_cast<long long>(previous_offset_ns));
  out = RecordInfo{};
  out.offset = offset;
  out.offset_ns = f.offset_ns;
  out.sequence = f.sequence;
  out.flags = f.flags;
  out.bytes = f.bytes;
  out.crc = f.crc;
  const uint64_t body = offset + kRecordHeaderBytes;
  if ((f.flags & kRecordRepeat) != 0) {
    uint8_t target[kRepeatStoredBytes];
    TLV_ASSIGN_OR_RETURN(const bool got,
                         pread_all(fd_, target, sizeof(target), body, path_.c_str()));
    if (!got) return false;
    out.data_offset = internal::get_u64(target);
    TLV_ENSURE(out.data_offset >= kRecordingHeaderBytes + kRecordHeaderBytes &&
                   out.data_offset + f.bytes <= offset,
               ErrorCode::kFormat,
               "recording %s: record %llu at offset %llu repeats bytes at %llu+%u, which are not "
               "an earlier record's",
               path_.c_str(), static_cast<unsigned long long>(index),
               static_cast<unsigned long long>(offset),
               static_cast<unsigned long long>(out.data_offset), f.bytes);
    out.next = body + kRepeatStoredBytes;
  } else {
    out.data_offset = body;
    out.next = body + f.bytes;
  }
  return out.next <= summary_.file_bytes;  // the bytes must all be there
}

Status RecordingReader::scan() {
  RecordingSummary& s = summary_;
  uint64_t at = kRecordingHeaderBytes;
  int64_t previous = 0;
  RecordInfo info;
  for (uint64_t index = 0;; ++index) {
    TLV_ASSIGN_OR_RETURN(const bool complete, parse_record(at, index, previous, info));
    if (!complete) break;
    if (s.frames == 0) {
      s.first_offset_ns = info.offset_ns;
      s.first_sequence = info.sequence;
    }
    ++s.frames;
    s.repeats += (info.flags & kRecordRepeat) != 0 ? 1 : 0;
    s.max_frame_bytes = std::max(s.max_frame_bytes, info.bytes);
    s.last_offset_ns = info.offset_ns;
    s.last_sequence = info.sequence;
    previous = info.offset_ns;
    at = info.next;
  }
  s.data_end = at;
  if (at < s.file_bytes) {  // a writer died mid-record: its last record is ignored
    s.truncated_records = 1;
    s.truncated_bytes = s.file_bytes - at;
  }
  return {};
}

Result<bool> RecordingReader::record_at(uint64_t offset, RecordInfo& out) const {
  if (offset >= summary_.data_end) return false;
  TLV_ASSIGN_OR_RETURN(const bool complete, parse_record(offset, 0, 0, out));
  TLV_ENSURE(complete, ErrorCode::kFormat, "recording %s: record at offset %llu is cut short",
             path_.c_str(), static_cast<unsigned long long>(offset));
  return true;
}

Status RecordingReader::read_frame(const RecordInfo& info, std::span<uint8_t> out,
                                   bool verify) const {
  TLV_ENSURE(out.size() >= info.bytes, ErrorCode::kInvalidArgument,
             "recording %s: a %u-byte frame does not fit a %zu-byte buffer", path_.c_str(),
             info.bytes, out.size());
  TLV_ASSIGN_OR_RETURN(const bool whole,
                       pread_all(fd_, out.data(), info.bytes, info.data_offset, path_.c_str()));
  TLV_ENSURE(whole, ErrorCode::kFormat, "recording %s: frame at offset %llu is cut short",
             path_.c_str(), static_cast<unsigned long long>(info.data_offset));
  if (verify) {
    TLV_ENSURE(crc32(out.data(), info.bytes) == info.crc, ErrorCode::kCaptureBadFrame,
               "recording %s: frame of record at offset %llu fails its checksum", path_.c_str(),
               static_cast<unsigned long long>(info.offset));
  }
  return {};
}

}  // namespace tlvlink::capture
