#pragma once
#ifndef TLVLINK_DAEMON_PRIVATE
#error "stream_sink.h is internal to firmware/tlvlinkd"
#endif
// The stream protocol (runtime/protocol) over a serial, pty or USB link (runtime/transport):
// records become stream messages (runtime/stream's MessageMapper) posted to the board's Sender,
// which never blocks (a slow or absent host costs queued messages, counted and reported in the
// next Stats). The controller's commands come back through the Sender to the daemon's command
// queue. The Hello is built once at start.

#include <memory>
#include <string>

#include "commands.h"
#include "output_sink.h"
#include "tlvlink/daemon/config.h"
#include "tlvlink/model.h"
#include "tlvlink/stream/hello.h"
#include "tlvlink/stream/message_mapper.h"
#include "tlvlink/transport/sender.h"

namespace tlvlink::daemon::internal {

class StreamSink final : public OutputSink {
 public:
  // `spec`: serial:..., pty:..., usb... (transport_spec.h). Commands go to `commands`.
  static Result<std::unique_ptr<StreamSink>> open(const std::string& spec,
                                                  const DaemonConfig& config, const Model& model,
                                                  const stream::OutputNames& names,
                                                  CommandQueue& commands);
  ~StreamSink() override;
  void record(const OutputRecord& record, int64_t written_ns) override;
  void stats(const RunTotals& totals, bool final) override;
  uint64_t failed() const override { return failed_; }
  void close() override;
  // A FrameImage, from the image encoder's thread: false (not posted) while the link is down or
  // its queue is over half full, so images never push predictions out of the queue.
  bool post_image(const stream::FrameImageRecord& image);

 private:
  explicit StreamSink(bool detected_grasps) : mapper_(detected_grasps) {}

  std::unique_ptr<transport::Sender> sender_;
  // Storage the Hello's views point into (kept for the Sender's copy and its re-sends).
  std::unique_ptr<stream::HelloBuilder> hello_;
  stream::MessageMapper mapper_;  // per-record scratch (no allocation per record)
  uint64_t failed_ = 0;
  bool closed_ = false;
};

}  // namespace tlvlink::daemon::internal
