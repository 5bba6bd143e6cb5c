#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "jsonl_writer.h is internal to firmware/tlvlinkd"
#endif
// The daemon's output as JSON lines (until the stream protocol carries it): one object per frame
// prediction, grasp prediction, event and stats report, each written with one write(2). Names
// (sensors, heads, labels) are resolved once at start. Schema: firmware/tlvlinkd/README.md.

#include <atomic>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "line_buffer.h"
#include "output_queue.h"
#include "tlvlink/error.h"
#include "tlvlink/stream/names.h"

namespace tlvlink::daemon::internal {

using stream::OutputNames;

class JsonlWriter {
 public:
  // "-" is stdout; otherwise the file is created or appended to.
  static Result<JsonlWriter> open(const std::string& target, OutputNames names);
  JsonlWriter() = default;
  JsonlWriter(JsonlWriter&& other) noexcept;
  JsonlWriter& operator=(JsonlWriter&&) = delete;
  JsonlWriter(const JsonlWriter&) = delete;
  ~JsonlWriter();

  // Each writes one line; a failed write (disk full, a line too long) is counted, not fatal. A
  // pipe whose reader left (EPIPE) closes the output: later lines are not written or counted.
  void write(const OutputRecord& record, int64_t written_ns);
  void write_line(const LineBuffer& line);
  LineBuffer& scratch() { return line_; }
  const OutputNames& names() const { return names_; }

  uint64_t lines() const { return lines_; }
  uint64_t failed_writes() const { return failed_; }
  bool closed() const { return closed_; }  // read by any thread
  // For the summary: "output jsonl:PATH: N record(s) not written (N: disk full)" and/or "closed
  // by its reader"; empty when nothing went wrong.
  std::string problem() const;

 private:
  void frame(const pipeline::FramePrediction& p, int64_t written_ns);
  void grasp(const pipeline::GraspPrediction& g);
  void event(const EventRecord& e);

  int fd_ = -1;
  bool owns_fd_ = false;
  std::string target_;  // "jsonl:PATH"
  OutputNames names_;
  LineBuffer line_;
  uint64_t lines_ = 0, failed_ = 0, too_long_ = 0;
  int last_errno_ = 0;
  std::atomic<bool> closed_{false};
};

}  // namespace tlvlink::daemon::internal
