// RecordingWriter: one write per record into a temporary file beside the target
// (tlvlink/atomic_file.h), renamed over it by close(): an existing recording is replaced only by
// a complete one. Within the temporary, a failed write is cut back to the last whole record.
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "recording_format.h"
#include "tlvlink/capture/recording.h"
#include "tlvlink/crc32.h"

namespace tlvlink::capture {

using internal::RecordFields;

Result<RecordingWriter> RecordingWriter::create(const std::string& path,
                                                const RecordingFormat& format,
                                                const WriterOptions& options) {
  TLV_TRY(internal::validate_recording_format(format, path.c_str()));
  // Without overwrite, an existing file is an error now rather than replaced at close().
  struct stat st {};
  TLV_ENSURE(options.overwrite || ::stat(path.c_str(), &st) != 0, ErrorCode::kIo,
             "recording %s: cannot create: %s", path.c_str(), std::strerror(EEXIST));
  auto file = AtomicFile::create(path.c_str());
  if (!file.ok()) return file.error().with_context("recording");
  RecordingWriter w;
  w.path_ = path;
  w.file_.emplace(std::move(file).value());
  w.fd_ = w.file_->fd();
  w.origin_ns_ = options.origin_ns;
  uint8_t header[kRecordingHeaderBytes];
  internal::encode_file_header(format, header);
  TLV_TRY(w.write_record(header, nullptr, 0));
  return w;
}

RecordingWriter::RecordingWriter(RecordingWriter&& o) noexcept
    : path_(std::move(o.path_)),
      file_(std::move(o.file_)),
      fd_(std::exchange(o.fd_, -1)),
      end_(o.end_),
      frames_(o.frames_),
      origin_ns_(o.origin_ns_),
      last_offset_ns_(o.last_offset_ns_) {}

RecordingWriter& RecordingWriter::operator=(RecordingWriter&& o) noexcept {
  if (this != &o) {
    (void)close();
    path_ = std::move(o.path_);
    file_ = std::move(o.file_);
    o.file_.reset();
    fd_ = std::exchange(o.fd_, -1);
    end_ = o.end_;
    frames_ = o.frames_;
    origin_ns_ = o.origin_ns_;
    last_offset_ns_ = o.last_offset_ns_;
  }
  return *this;
}

RecordingWriter::~RecordingWriter() { (void)close(); }

// Writes header (+ data) at end_ with as many writev calls as it takes; on failure the file is
// cut back to end_ so a later append starts at a record boundary again.
Status RecordingWriter::write_record(const uint8_t* header, const uint8_t* data,
                                     size_t data_bytes) {
  TLV_ENSURE(fd_ >= 0, ErrorCode::kInvalidState, "recording %s: writer is closed", path_.c_str());
  const size_t header_bytes = end_ == 0 ? kRecordingHeaderBytes : kRecordHeaderBytes;
  iovec iov[2] = {{const_cast<uint8_t*>(header), header_bytes},
                  {const_cast<uint8_t*>(data), data_bytes}};
  const size_t total = header_bytes + data_bytes;
  size_t done = 0;
  while (done < total) {
    iovec part[2];
    int count = 0;
    size_t skip = done;
    for (const iovec& v : iov) {
      if (skip >= v.iov_len) {
        skip -= v.iov_len;
        continue;
      }
      part[count++] = {static_cast<uint8_t*>(v.iov_base) + skip, v.iov_len - skip};
      skip = 0;
    }
    const ssize_t n = ::pwritev(fd_, part, count, static_cast<off_t>(end_ + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : EIO;
      if (::ftruncate(fd_, static_cast<off_t>(end_)) != 0) {
        return Error::make(ErrorCode::kIo,
                           "recording %s: write at offset %llu failed (%s) and the partial "
                           "record could not be cut off (%s)",
                           path_.c_str(), static_cast<unsigned long long>(end_), std::strerror(err),
                           std::strerror(errno));
      }
      return Error::make(ErrorCode::kIo, "recording %s: write at offset %llu failed: %s",
                         path_.c_str(), static_cast<unsigned long long>(end_), std::strerror(err));
    }
    done += static_cast<size_t>(n);
  }
  end_ += total;
  return {};
}

Result<int64_t> RecordingWriter::offset_of(int64_t timestamp_ns) {
  if (origin_ns_ < 0) origin_ns_ = timestamp_ns;
  const int64_t offset = timestamp_ns - origin_ns_;
  TLV_ENSURE(offset >= 0, ErrorCode::kInvalidArgument,
             "recording %s: frame %llu at %lld ns is before the origin %lld ns", path_.c_str(),
             static_cast<unsigned long long>(frames_), static_cast<long long>(timestamp_ns),
             static_cast<long long>(origin_ns_));
  TLV_ENSURE(offset >= last_offset_ns_, ErrorCode::kInvalidArgument,
             "recording %s: frame %llu at offset %lld ns is earlier than the previous frame "
             "(%lld ns)",
             path_.c_str(), static_cast<unsigned long long>(frames_),
             static_cast<long long>(offset), static_cast<long long>(last_offset_ns_));
  return offset;
}

Result<RecordedBytes> RecordingWriter::append(std::span<const uint8_t> bytes, int64_t timestamp_ns,
                                              uint32_t sequence, uint32_t flags) {
  TLV_ENSURE((flags & ~kRecordErrorFlag) == 0, ErrorCode::kInvalidArgument,
             "recording %s: append() flags 0x%x (only kRecordErrorFlag)", path_.c_str(), flags);
  TLV_ENSURE(bytes.size() <= kMaxRecordedFrameBytes, ErrorCode::kInvalidArgument,
             "recording %s: frame of %zu bytes is over the limit of %u", path_.c_str(),
             bytes.size(), kMaxRecordedFrameBytes);
  TLV_ASSIGN_OR_RETURN(const int64_t offset, offset_of(timestamp_ns));
  RecordFields r;
  r.flags = flags;
  r.offset_ns = offset;
  r.sequence = sequence;
  r.bytes = static_cast<uint32_t>(bytes.size());
  r.crc = crc32(bytes.data(), bytes.size());
  uint8_t header[kRecordHeaderBytes];
  internal::encode_record_header(r, header);
  const uint64_t at = end_ + kRecordHeaderBytes;
  TLV_TRY(write_record(header, bytes.data(), bytes.size()));
  ++frames_;
  last_offset_ns_ = offset;
  return RecordedBytes{at, r.bytes, r.crc};
}

Status RecordingWriter::append_repeat(const RecordedBytes& bytes, int64_t timestamp_ns,
                                      uint32_t sequence, uint32_t flags) {
  TLV_ENSURE((flags & ~kRecordErrorFlag) == 0, ErrorCode::kInvalidArgument,
             "recording %s: append_repeat() flags 0x%x (only kRecordErrorFlag)", path_.c_str(),
             flags);
  TLV_ENSURE(bytes.offset >= kRecordingHeaderBytes + kRecordHeaderBytes &&
                 bytes.offset + bytes.size <= end_,
             ErrorCode::kInvalidArgument,
             "recording %s: repeat of bytes at %llu+%u, not inside this recording (%llu bytes)",
             path_.c_str(), static_cast<unsigned long long>(bytes.offset), bytes.size,
             static_cast<unsigned long long>(end_));
  TLV_ASSIGN_OR_RETURN(const int64_t offset, offset_of(timestamp_ns));
  RecordFields r;
  r.flags = flags | kRecordRepeat;
  r.offset_ns = offset;
  r.sequence = sequence;
  r.bytes = bytes.size;
  r.crc = bytes.crc;
  uint8_t header[kRecordHeaderBytes];
  internal::encode_record_header(r, header);
  uint8_t target[kRepeatStoredBytes];
  internal::put_u64(target, bytes.offset);
  TLV_TRY(write_record(header, target, sizeof(target)));
  ++frames_;
  last_offset_ns_ = offset;
  return {};
}

Status RecordingWriter::sync() {
  TLV_ENSURE(fd_ >= 0, ErrorCode::kInvalidState, "recording %s: writer is closed", path_.c_str());
  TLV_ENSURE(::fdatasync(fd_) == 0, ErrorCode::kIo, "recording %s: fdatasync: %s", path_.c_str(),
             std::strerror(errno));
  return {};
}

Status RecordingWriter::close() {
  if (fd_ < 0) return {};
  fd_ = -1;
  // fsync, rename over the path, fsync the directory; a failure leaves any old file as it was.
  Status s = file_->commit();
  file_.reset();
  if (!s.ok()) return s.error().with_context("recording");
  return {};
}

}  // namespace tlvlink::capture
