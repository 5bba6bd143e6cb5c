#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "stream_sink.h is internal to firmware/tlvlinkd"
#endif
// The stream protocol (runtime/protocol) over a serial, pty or USB link (runtime/transport):
// records become FramePrediction / GraspPrediction / Error / Stats messages posted to the
// board's Sender, which never blocks (a slow or absent host costs queued messages, counted and
// reported in the next Stats). The controller's commands come back through the Sender to the
// daemon's command queue. Names and the Hello are built once at start.

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "jsonl_writer.h"
#include "output_sink.h"
#include "tlvlink/daemon/config.h"
#include "tlvlink/model.h"
#include "tlvlink/protocol/messages.h"
#include "tlvlink/transport/sender.h"

namespace tlvlink::daemon::internal {

class StreamSink final : public OutputSink {
 public:
  // `spec`: serial:..., pty:..., usb... (transport_spec.h). Commands go to `commands`.
  static Result<std::unique_ptr<StreamSink>> open(const std::string& spec, const DaemonConfig& config,
                                                  const Model& model, const OutputNames& names,
                                                  CommandQueue& commands);
  ~StreamSink() override;
  void record(const OutputRecord& record, int64_t written_ns) override;
  void stats(const RunTotals& totals, bool final) override;
  uint64_t failed() const override { return failed_; }
  void close() override;

 private:
  StreamSink() = default;
  void build_hello(const DaemonConfig& config, const Model& model, const OutputNames& names);

  std::unique_ptr<transport::Sender> sender_;
  uint64_t failed_ = 0;
  bool detected_ = false;  // grasp mode "detected": GraspPrediction.phase_source
  bool closed_ = false;
  // Storage the Hello's views point into (kept for the Sender's copy and its re-sends).
  std::vector<std::string> strings_;
  std::vector<std::vector<std::string_view>> label_views_;
  std::vector<protocol::SensorInfo> sensors_;
  std::vector<protocol::HeadInfo> heads_;
  std::vector<std::string_view> stage_names_;
  // Per-record scratch (no allocation per record).
  std::array<protocol::HeadOutput, pipeline::kMaxHeads> head_outputs_{};
  std::array<uint32_t, 6> stage_ns_{};
  std::array<protocol::GraspFrame, pipeline::kMaxGraspFrames> grasp_frames_{};
  std::array<protocol::SensorStats, pipeline::kMaxSensors> sensor_stats_{};
  std::array<protocol::DropCount, 8> drops_{};
};

}  // namespace tlvlink::daemon::internal
