#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "jsonl_writer.h is internal to firmware/tlvlinkd"
#endif
// Where the daemon's JSON lines go: stdout or a file, each line written with one write(2) from a
// fixed line buffer (no heap). What the lines say is the sink's (jsonl_sink.h).

#include <atomic>
#include <cstdint>
#include <string>

#include "tlvlink/error.h"
#include "tlvlink/stream/line_buffer.h"

namespace tlvlink::daemon::internal {

class JsonlWriter {
 public:
  // Long enough for a frame with a 256-wide embedding and its int8 tensor, or a Hello of many
  // heads; a longer line is counted as not written (problem()), never cut.
  static constexpr size_t kLineCapacity = 16384;
  using Line = stream::FixedLineBuffer<kLineCapacity>;

  // "-" is stdout; otherwise the file is created or appended to.
  static Result<JsonlWriter> open(const std::string& target);
  JsonlWriter() = default;
  JsonlWriter(JsonlWriter&& other) noexcept;  // the line buffer is scratch: not moved
  JsonlWriter& operator=(JsonlWriter&&) = delete;
  JsonlWriter(const JsonlWriter&) = delete;
  ~JsonlWriter();

  // The buffer the next line is formatted into (cleared).
  stream::LineBuffer& start_line() {
    line_.clear();
    return line_;
  }
  // Writes the line formatted into start_line()'s buffer; a failed write (disk full, a line too
  // long) is counted, not fatal. A pipe whose reader left (EPIPE) closes the output: later
  // lines are not written or counted.
  void write_line();

  uint64_t lines() const { return lines_; }
  uint64_t failed_writes() const { return failed_; }
  bool closed() const { return closed_; }  // read by any thread
  // For the summary: "output jsonl:PATH: N record(s) not written (N: disk full)" and/or "closed
  // by its reader"; empty when nothing went wrong.
  std::string problem() const;

 private:
  int fd_ = -1;
  bool owns_fd_ = false;
  std::string target_;  // "jsonl:PATH"
  Line line_;
  uint64_t lines_ = 0, failed_ = 0, too_long_ = 0;
  int last_errno_ = 0;
  std::atomic<bool> closed_{false};
};

}  // namespace tlvlink::daemon::internal
