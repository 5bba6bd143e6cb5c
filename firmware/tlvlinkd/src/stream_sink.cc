#include "stream_sink.h"

#include "board_hello.h"
#include "clock.h"
#include "tlvlink/log.h"
#include "tlvlink/transport/transport_spec.h"

namespace tlvlink::daemon::internal {
namespace {

TLV_LOG_CATEGORY(kLogStream, "stream");

}  // namespace

Result<std::unique_ptr<StreamSink>> StreamSink::open(const std::string& spec,
                                                     const DaemonConfig& config, const Model& model,
                                                     const stream::OutputNames& names,
                                                     CommandQueue& commands) {
  auto sink = std::unique_ptr<StreamSink>(new StreamSink(config.processing.grasp_options.mode ==
                                                         pipeline::GraspOptions::Mode::kDetected));
  auto link = transport::make_transport(spec);
  if (!link.ok()) return link.error().with_context("output '%s'", spec.c_str());
  TLV_ASSIGN_OR_RETURN(sink->sender_, transport::Sender::create(std::move(link).value(), {}));
  sink->hello_ = make_hello(config, model, names);
  TLV_TRY(sink->sender_->set_hello(sink->hello_->hello()));
  TLV_TRY(sink->sender_->set_command_handler([&commands](const protocol::Command& c) -> Status {
    TLV_ASSIGN_OR_RETURN(const Command cmd, stream::from_protocol(c, board_clock_ns()));
    TLV_ENSURE(commands.push(cmd), ErrorCode::kInvalidState, "command queue full");
    return {};
  }));
  TLV_TRY(sink->sender_->start());
  return sink;
}

StreamSink::~StreamSink() { close(); }

void StreamSink::close() {
  if (closed_ || sender_ == nullptr) return;
  closed_ = true;
  sender_->stop();  // sends what is queued for up to flush_ms
  const transport::SenderCounters c = sender_->counters();
  TLV_LOG(kLogStream, kInfo,
          "stream: %llu messages posted, %llu frames sent, dropped %llu (queue full) "
          "%llu (link down) %llu (stale)",
          static_cast<unsigned long long>(c.posted), static_cast<unsigned long long>(c.frames_sent),
          static_cast<unsigned long long>(c.dropped_queue_full),
          static_cast<unsigned long long>(c.dropped_link_down),
          static_cast<unsigned long long>(c.dropped_stale));
  // What the flush could not send in time is lost with the process: say so (the frame being
  // written at the deadline has left the queue and is not counted).
  if (c.queue_messages > 0) {
    TLV_LOG(kLogStream, kWarning,
            "stream: %u queued messages not sent at stop (the link did not take them within "
            "the flush time)",
            c.queue_messages);
  }
}

void StreamSink::record(const OutputRecord& record, int64_t) {
  Status st;
  if (const auto* p = std::get_if<pipeline::FramePrediction>(&record)) {
    st = sender_->post(mapper_.frame(*p));
  } else if (const auto* g = std::get_if<pipeline::GraspPrediction>(&record)) {
    st = sender_->post(mapper_.grasp(*g));
  } else {
    const EventRecord& e = std::get<EventRecord>(record);
    st = sender_->post(stream::MessageMapper::event(e.error, e.sensor, e.text.data()));
  }
  failed_ += st.ok() ? 0 : 1;
}

bool StreamSink::post_image(const stream::FrameImageRecord& image) {
  const transport::SenderCounters c = sender_->counters();
  if (!c.link_up || 2 * static_cast<uint64_t>(c.queue_bytes) > c.queue_capacity_bytes) return false;
  return sender_->post(stream::MessageMapper::image(image)).ok();
}

void StreamSink::stats(const RunTotals& r, bool) {
  failed_ += sender_->post(mapper_.stats(stream_totals(r))).ok() ? 0 : 1;
}

}  // namespace tlvlink::daemon::internal
