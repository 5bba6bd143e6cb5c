#include "stream_sink.h"

#include <unistd.h>

#include <vector>

#include "clock.h"
#include "tlvlink/log.h"
#include "tlvlink/transport/transport_spec.h"

namespace tlvlink::daemon::internal {
namespace {

TLV_LOG_CATEGORY(kLogStream, "stream");

#ifndef TLVLINK_BOARD_NAME
#define TLVLINK_BOARD_NAME "unknown"
#endif
#ifndef TLVLINK_VERSION
#define TLVLINK_VERSION "0"
#endif

}  // namespace

Result<std::unique_ptr<StreamSink>> StreamSink::open(const std::string& spec,
                                                     const DaemonConfig& config, const Model& model,
                                                     const OutputNames& names,
                                                     CommandQueue& commands) {
  auto sink = std::unique_ptr<StreamSink>(new StreamSink(config.processing.grasp_options.mode ==
                                                         pipeline::GraspOptions::Mode::kDetected));
  auto link = transport::make_transport(spec);
  if (!link.ok()) return link.error().with_context("output '%s'", spec.c_str());
  TLV_ASSIGN_OR_RETURN(sink->sender_, transport::Sender::create(std::move(link).value(), {}));
  char host[256] = "board";
  gethostname(host, sizeof host - 1);
  const stream::BoardIdentity board{host, TLVLINK_BOARD_NAME, TLVLINK_VERSION,
                                    static_cast<uint64_t>(getpid())};
  std::vector<stream::SensorDescription> sensors;
  for (const SensorConfig& s : config.sensors) {
    sensors.push_back({s.name, s.sensor_model, image::pixel_format_name(s.format.format),
                       s.format.width, s.format.height, s.fps});
  }
  sink->hello_.emplace(board, model, config.model, sensors, names);
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
  stream::StreamTotals t;
  t.seconds = r.seconds;
  t.sensors = r.sensors;
  t.sensor_fps = r.sensor_fps;
  t.sensor_frames = r.sensor_frames;
  t.sensor_encoded = r.sensor_encoded;
  t.sensor_gated = r.sensor_gated;
  t.capture_gap = r.drops_sequence;
  t.capture_error = r.bad_frames + r.decode_errors;
  // Camera frames skipped for a newer one (the capture thread busy) and decoded frames dropped
  // (inference behind) are both inference_busy; the stream's "stale" is the Sender's (messages
  // too old to send), and its queue_full is added to this output queue's (one entry a cause).
  t.inference_busy = r.drops_stale + r.drops_queue;
  t.queue_full = r.drops_output;
  t.frame_images = r.frame_images;
  t.image_busy = r.drops_image;
  t.cpu_percent = r.process_cpu_pct;
  t.cpu_cores = static_cast<uint8_t>(sysconf(_SC_NPROCESSORS_ONLN));
  t.rss_bytes = static_cast<uint64_t>(r.peak_rss_kb) * 1024;
  failed_ += sender_->post(mapper_.stats(t)).ok() ? 0 : 1;
}

}  // namespace tlvlink::daemon::internal
