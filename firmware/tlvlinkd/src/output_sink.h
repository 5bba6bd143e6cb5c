#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "output_sink.h is internal to firmware/tlvlinkd"
#endif
// Where the output thread sends records: JSON lines (a file or stdout) or the stream protocol
// over a serial or USB link. Called on the output thread only; must not allocate per record.

#include <cstdint>
#include <string>

#include "output_queue.h"
#include "run_totals.h"

namespace tlvlink::daemon::internal {

class OutputSink {
 public:
  virtual ~OutputSink() = default;
  virtual void record(const OutputRecord& record, int64_t written_ns) = 0;
  virtual void stats(const RunTotals& totals, bool final) = 0;
  virtual uint64_t failed() const = 0;  // records that could not be written or queued
  // The reader went away for good (a closed pipe); safe to call from any thread.
  virtual bool closed() const { return false; }
  // For the summary, after the run: what failed and why ("" when nothing did).
  virtual std::string problem() const { return {}; }
  virtual void close() {}  // flush what is pending (the end of a session)
};

}  // namespace tlvlink::daemon::internal
