#pragma once
// Recording files (`tlvlink listen --record FILE`; format in tools/listen/README.md): the bytes
// as they were read from the link, each chunk with the host time it arrived, plus link up/down
// events and the commands the host sent. Replaying feeds the same bytes, at the same recorded
// times, to the same decoder: every client sees exactly what the live one saw (frames,
// rejections, gaps, latencies).

#include <cstdint>
#include <cstdio>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::listen {

inline constexpr char kRecordingMagic[8] = {'T', 'L', 'V', 'L', 'R', 'E', 'C', '\n'};
inline constexpr uint16_t kRecordingVersion = 1;
inline constexpr size_t kRecordingHeaderSize = 32;
inline constexpr size_t kRecordHeaderSize = 16;
inline constexpr size_t kMaxRecordLength = 1 << 20;

enum class RecordKind : uint8_t {
  kReceived = 0,  // bytes read from the link
  kLinkUp = 1,    // text: what was opened
  kLinkDown = 2,  // text: why it went down
  kSent = 3,      // bytes the host wrote: commands its user sent
  kSentAuto = 4,  // bytes the host wrote: the client's own Info and TimeSync (their replies are
                  // consumed by the client, not delivered; a replay needs to know which)
};

struct Record {
  RecordKind kind = RecordKind::kReceived;
  int64_t time_ns = 0;  // host CLOCK_MONOTONIC
  std::vector<std::byte> data;
};

// Creates a recording file of any format (.tlvrec, .mcap) by one rule: an existing file is an
// error unless `overwrite` (then it is truncated); anything but a regular file (a FIFO, a
// device) is refused without blocking. `what` names the file in errors ("recording").
Result<std::FILE*> create_recording_file(const std::string& path, bool overwrite,
                                         const char* what = "recording");

// Where a client writes what it reads and sends (a .tlvrec file, or another container that
// carries the same records: tools/foxglove's MCAP recordings).
class RecordSink {
 public:
  virtual ~RecordSink() = default;
  virtual Status write(RecordKind kind, int64_t time_ns, std::span<const std::byte> data) = 0;
  virtual Status flush() = 0;
};

// Where a replaying client reads records from.
class RecordSource {
 public:
  virtual ~RecordSource() = default;
  // The next record; false at the end.
  virtual Result<bool> next(Record& record) = 0;
  // The last record was cut short (its writer was killed while writing).
  virtual bool truncated() const = 0;
};

class RecordingWriter : public RecordSink {
 public:
  // Creates the file and writes its header with the current wall and monotonic times. An
  // existing file is an error unless `overwrite` (then it is truncated); anything but a regular
  // file (a FIFO, a device) is refused without blocking. Write errors name the path and the
  // reason ("disk full", "file size limit reached").
  static Result<std::unique_ptr<RecordingWriter>> create(const std::string& path,
                                                         bool overwrite = false);
  ~RecordingWriter() override;
  Status write(RecordKind kind, int64_t time_ns, std::span<const std::byte> data) override;
  Status flush() override;

 private:
  explicit RecordingWriter(std::FILE* file, std::string path)
      : file_(file), path_(std::move(path)) {}
  std::FILE* file_;
  std::string path_;
};

class RecordingReader : public RecordSource {
 public:
  static Result<std::unique_ptr<RecordingReader>> open(const std::string& path);
  ~RecordingReader() override;
  int64_t start_wall_ns() const { return start_wall_ns_; }
  int64_t start_monotonic_ns() const { return start_mono_ns_; }
  // The next record; false at the end. A record cut short (the recorder was killed while
  // writing) ends the file: truncated() says so.
  Result<bool> next(Record& record) override;
  bool truncated() const override { return truncated_; }

 private:
  RecordingReader(std::FILE* file, std::string path) : file_(file), path_(std::move(path)) {}
  std::FILE* file_;
  std::string path_;
  int64_t start_wall_ns_ = 0, start_mono_ns_ = 0;
  bool truncated_ = false;
};

}  // namespace tlvlink::listen
