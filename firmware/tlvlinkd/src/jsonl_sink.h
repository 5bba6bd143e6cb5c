#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "jsonl_sink.h is internal to firmware/tlvlinkd"
#endif
// JSON lines: one object per frame prediction, grasp prediction, event, stats and summary
// (schema: firmware/tlvlinkd/README.md), each written with one write(2).

#include "jsonl_writer.h"
#include "output_sink.h"

namespace tlvlink::daemon::internal {

class JsonlSink final : public OutputSink {
 public:
  explicit JsonlSink(JsonlWriter writer) : writer_(std::move(writer)) {}
  void record(const OutputRecord& record, int64_t written_ns) override {
    writer_.write(record, written_ns);
  }
  void stats(const RunTotals& totals, bool final) override;
  uint64_t failed() const override { return writer_.failed_writes(); }
  bool closed() const override { return writer_.closed(); }
  std::string problem() const override { return writer_.problem(); }

 private:
  JsonlWriter writer_;
};

}  // namespace tlvlink::daemon::internal
