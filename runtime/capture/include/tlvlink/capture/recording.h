#pragma once
// Recorded raw streams: what a camera emitted, frame by frame, in a file a board can write and
// replay (replay_source.h) with nothing but POSIX I/O. The byte layout is documented in
// runtime/capture/README.md ("Recorded raw streams"); in short, all integers little-endian:
// (files are named *.tlvraw; the stream protocol's recordings, tools/listen, are *.tlvrec)
//
//   file header, 64 bytes: magic "\x89TLVREC\n", version 1, header size, V4L2 fourcc, width,
//     height, stride, nominal fps as numerator/denominator, flags, CLOCK_REALTIME of the origin,
//     CRC-32 of the header;
//   then one record per frame: a 32-byte record header (magic "FRM1", flags, capture offset in
//     ns from the recording's origin, the driver's 32-bit sequence, frame bytes, CRC-32 of the
//     frame bytes, CRC-32 of the record header) followed by the frame's bytes, or by the 8-byte
//     file offset of an earlier record's bytes when the record repeats them (kRecordRepeat).
//
// There is no trailing index: a reader scans the record headers at open (one 32-byte pread per
// frame). So a writer that dies loses nothing it already wrote: every append is one write of a
// whole record, and a reader ignores (and counts) a truncated final record.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "tlvlink/atomic_file.h"
#include "tlvlink/error.h"
#include "tlvlink/image/pixel_format.h"

namespace tlvlink::capture {

inline constexpr uint16_t kRecordingVersion = 1;
inline constexpr size_t kRecordingHeaderBytes = 64;
inline constexpr size_t kRecordHeaderBytes = 32;
inline constexpr size_t kRepeatStoredBytes = 8;  // what follows the header of a repeat record
// Largest frame a recording may hold (a Mini MJPEG frame is ~0.65 MB; its worst case 32 MB).
inline constexpr uint32_t kMaxRecordedFrameBytes = 256u << 20;
inline constexpr int32_t kMaxRecordedSide = 16384;

// Record flags.
inline constexpr uint32_t kRecordErrorFlag = 1u << 0;  // the driver flagged the buffer
inline constexpr uint32_t kRecordRepeat = 1u << 1;     // bytes are an earlier record's
inline constexpr uint32_t kRecordKnownFlags = kRecordErrorFlag | kRecordRepeat;

// What the camera streamed, stored once in the file header.
struct RecordingFormat {
  image::FrameFormat format;   // pixel format, size, stride
  uint32_t fps_numerator = 0;  // nominal frame rate = numerator / denominator; 0/1 = unknown
  uint32_t fps_denominator = 1;
  int64_t origin_realtime_ns = 0;  // CLOCK_REALTIME at the origin (informative; 0 unknown)

  double nominal_fps() const {
    return fps_denominator > 0 ? static_cast<double>(fps_numerator) / fps_denominator : 0.0;
  }
};

// Where an appended frame's bytes live, for repeating them later without storing them again.
struct RecordedBytes {
  uint64_t offset = 0;  // file offset of the bytes
  uint32_t size = 0;
  uint32_t crc = 0;
};

struct WriterOptions {
  // The time the capture offsets count from, in the timestamps' clock. < 0: the first frame's
  // timestamp (its offset is 0). Sources recorded together share one origin, so the phase
  // between two cameras survives (the second camera's first frame may sit at +7 ms).
  int64_t origin_ns = -1;
  bool overwrite = false;  // replace an existing file (else an existing file is an error)
};

// Appends frames to a new recording, in a temporary beside `path` until close() renames it into
// place, so an existing file is replaced only by a complete recording. Every append is one
// write() of the whole record: a process that dies leaves the temporary
// (".NAME.tmp-XXXXXX") with at most a truncated final record, which readers skip. append() does
// not allocate. Not thread-safe; non-copyable (owns the file).
class RecordingWriter {
 public:
  // Starts `path` as a temporary beside it (tlvlink/atomic_file.h) and writes the file header;
  // close() (or the destructor) renames it into place. Errors name the path.
  static Result<RecordingWriter> create(const std::string& path, const RecordingFormat& format,
                                        const WriterOptions& options = {});
  RecordingWriter(RecordingWriter&& other) noexcept;
  RecordingWriter& operator=(RecordingWriter&& other) noexcept;
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;
  ~RecordingWriter();  // close() without reporting

  // One frame as the camera delivered it. timestamp_ns must not be earlier than the origin or
  // the previous frame's timestamp (kInvalidArgument); flags: kRecordErrorFlag or 0. A failed
  // write is cut back off the file, so the recording stays readable.
  Result<RecordedBytes> append(std::span<const uint8_t> bytes, int64_t timestamp_ns,
                               uint32_t sequence, uint32_t flags = 0);
  // A frame whose bytes equal those of an earlier append (e.g. a static scene's frame reused):
  // stored as a 40-byte record pointing at them.
  Status append_repeat(const RecordedBytes& bytes, int64_t timestamp_ns, uint32_t sequence,
                       uint32_t flags = 0);

  // fdatasync(): survives a power loss, not only a process death.
  Status sync();
  // Syncs, closes and renames the recording into place; later appends fail. Idempotent.
  Status close();

  uint64_t frames() const { return frames_; }
  uint64_t file_bytes() const { return end_; }
  const std::string& path() const { return path_; }

 private:
  RecordingWriter() = default;
  Status write_record(const uint8_t* header, const uint8_t* data, size_t data_bytes);
  Result<int64_t> offset_of(int64_t timestamp_ns);

  std::string path_;
  std::optional<AtomicFile> file_;  // the temporary until close()
  int fd_ = -1;                     // file_'s descriptor while open
  uint64_t end_ = 0;
  uint64_t frames_ = 0;
  int64_t origin_ns_ = -1;
  int64_t last_offset_ns_ = 0;
};

// One record as the scan found it.
struct RecordInfo {
  uint64_t offset = 0;       // file offset of the record header
  uint64_t next = 0;         // file offset of the following record
  uint64_t data_offset = 0;  // where the frame's bytes are (an earlier record's for a repeat)
  int64_t offset_ns = 0;     // capture time - origin
  uint32_t sequence = 0;
  uint32_t flags = 0;
  uint32_t bytes = 0;
  uint32_t crc = 0;  // CRC-32 of the frame's bytes
};

// What the scan at open found.
struct RecordingSummary {
  RecordingFormat format;
  uint16_t version = 0;
  uint64_t frames = 0;           // complete records
  uint64_t repeats = 0;          // of which repeat earlier bytes
  uint32_t max_frame_bytes = 0;  // sizes a replay's buffers
  int64_t first_offset_ns = 0, last_offset_ns = 0;
  uint32_t first_sequence = 0, last_sequence = 0;
  uint64_t data_end = 0;  // end of the last complete record
  uint64_t file_bytes = 0;
  uint64_t truncated_records = 0;  // 0 or 1: an incomplete final record, ignored
  uint64_t truncated_bytes = 0;    // its bytes
};

// Reads a recording: the header and a scan of every record header at open (allocates the path
// only), then records and frame bytes by pread without allocating. A malformed file is a
// kFormat error naming the path, the record and its file offset; an unreadable one kIo.
class RecordingReader {
 public:
  static Result<RecordingReader> open(const std::string& path);
  RecordingReader(RecordingReader&& other) noexcept;
  RecordingReader& operator=(RecordingReader&& other) noexcept;
  RecordingReader(const RecordingReader&) = delete;
  RecordingReader& operator=(const RecordingReader&) = delete;
  ~RecordingReader();

  const RecordingSummary& summary() const { return summary_; }
  const std::string& path() const { return path_; }
  uint64_t first_record() const { return kRecordingHeaderBytes; }

  // The record at `offset` (first_record() or a previous RecordInfo::next); false past the
  // last complete record. Checks the header again (the file may have changed since the scan).
  Result<bool> record_at(uint64_t offset, RecordInfo& out) const;
  // The frame's bytes into out[0, info.bytes) (out must hold them). verify: compare the CRC-32
  // (kCaptureBadFrame naming the file and offset on a mismatch).
  Status read_frame(const RecordInfo& info, std::span<uint8_t> out, bool verify) const;

 private:
  RecordingReader() = default;
  Status scan();
  // Decodes and checks the record header at `offset`; index = the record's number for errors.
  Result<bool> parse_record(uint64_t offset, uint64_t index, int64_t previous_offset_ns,
                            RecordInfo& out) const;

  std::string path_;
  int fd_ = -1;
  RecordingSummary summary_;
};

}  // namespace tlvlink::capture
