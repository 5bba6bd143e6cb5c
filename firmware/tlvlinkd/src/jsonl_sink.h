#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "jsonl_sink.h is internal to firmware/tlvlinkd"
#endif
// JSON lines: the stream's messages in the one JSON-lines form (runtime/stream json_lines.h, the
// keys `tlvlink listen --json` prints): a Hello first, then one line per frame prediction, grasp
// prediction, event (an ErrorReport) and stats report, each written with one write(2). Records
// become messages with runtime/stream's MessageMapper, as on the stream link; what only the
// daemon has (a frame's int8 tensor, the run report of a stats line) follows the message's keys.
// Schema: firmware/tlvlinkd/README.md.

#include <memory>

#include "jsonl_writer.h"
#include "output_sink.h"
#include "tlvlink/stream/hello.h"
#include "tlvlink/stream/json_lines.h"
#include "tlvlink/stream/message_mapper.h"

namespace tlvlink::daemon::internal {

class JsonlSink final : public OutputSink {
 public:
  // Writes the Hello at once. `hello` names the sensors and heads of every later line.
  JsonlSink(JsonlWriter writer, std::unique_ptr<stream::HelloBuilder> hello, bool detected_grasps);
  void record(const OutputRecord& record, int64_t written_ns) override;
  void stats(const RunTotals& totals, bool final) override;
  uint64_t failed() const override { return writer_.failed_writes(); }
  bool closed() const override { return writer_.closed(); }
  std::string problem() const override { return writer_.problem(); }

 private:
  // Lines are numbered from 0 (the Hello) and stamped with when they were written, as the
  // stream's frame header would be.
  stream::JsonHeader header(int64_t written_ns) { return {sequence_++, 0, written_ns}; }

  JsonlWriter writer_;
  std::unique_ptr<stream::HelloBuilder> hello_;
  stream::MessageMapper mapper_;  // per-record scratch (no allocation per record)
  uint32_t sequence_ = 0;
};

}  // namespace tlvlink::daemon::internal
