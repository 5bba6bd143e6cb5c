#include "stream_sink.h"

#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <limits>

#include "tlvlink/heads/grasp_layout.h"
#include "tlvlink/log.h"
#include "tlvlink/transport/transport_spec.h"

namespace tlvlink::daemon::internal {
namespace {

TLV_LOG_CATEGORY(kLogStream, "stream");

// The stages a FramePrediction's stage_ns carries, in this order (named in the Hello): the
// JSON lines' and the stats' stages up to the heads (run_totals.h). There is no "gate" stage:
// the contact gate has no timestamp of its own (its microseconds are in "queue").
constexpr std::array<const char*, 6> kStageNames = {"dequeue", "decode", "queue",
                                                    "preprocess", "encoder", "heads"};

uint32_t span_ns(int64_t from, int64_t to) {
  if (from <= 0 || to < from) return 0;
  return static_cast<uint32_t>(std::min<int64_t>(to - from, std::numeric_limits<uint32_t>::max()));
}

#ifndef TLVLINK_BOARD_NAME
#define TLVLINK_BOARD_NAME "unknown"
#endif
#ifndef TLVLINK_VERSION
#define TLVLINK_VERSION "0"
#endif

}  // namespace

Result<std::unique_ptr<StreamSink>> StreamSink::open(const std::string& spec,
                                                      const DaemonConfig& config,
                                                      const Model& model, const OutputNames& names,
                                                      CommandQueue& commands) {
  auto sink = std::unique_ptr<StreamSink>(new StreamSink());
  sink->detected_ = config.processing.grasp_options.mode == pipeline::GraspOptions::Mode::kDetected;
  auto link = transport::make_transport(spec);
  if (!link.ok()) return link.error().with_context("output '%s'", spec.c_str());
  TLV_ASSIGN_OR_RETURN(sink->sender_, transport::Sender::create(std::move(link).value(), {}));
  sink->build_hello(config, model, names);
  protocol::Hello hello;
  hello.device = sink->strings_[0];
  hello.board = TLVLINK_BOARD_NAME;
  hello.firmware_version = TLVLINK_VERSION;
  hello.boot_id = static_cast<uint64_t>(getpid());
  hello.model_id = sink->strings_[1];
  hello.model_checksum = model.metadata().provenance.content_checksum;
  hello.sensors = sink->sensors_;
  hello.heads = sink->heads_;
  hello.stage_names = sink->stage_names_;
  hello.embedding_dim = static_cast<uint16_t>(model.metadata().embedding_dim);
  TLV_TRY(sink->sender_->set_hello(hello));
  TLV_TRY(sink->sender_->set_command_handler([&commands](const protocol::Command& c) -> Status {
    Command cmd;
    cmd.t_ns = c.event_ns;
    switch (c.kind) {
      case protocol::CommandKind::kGraspClosed: cmd.kind = CommandKind::kClosed; break;
      case protocol::CommandKind::kGraspLifting: cmd.kind = CommandKind::kLifting; break;
      case protocol::CommandKind::kRezero:
        cmd.kind = CommandKind::kRezero;
        cmd.sensor = c.sensor == protocol::kNoSensor ? -1 : c.sensor;
        break;
      default:
        return Error::make(ErrorCode::kProtocolUnsupported, "tlvlinkd does not take this command yet");
    }
    if (cmd.t_ns <= 0) {
      timespec ts{};
      clock_gettime(CLOCK_MONOTONIC, &ts);
      cmd.t_ns = static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
    }
    TLV_ENSURE(commands.push(cmd), ErrorCode::kInvalidState, "command queue full");
    return {};
  }));
  TLV_TRY(sink->sender_->start());
  return sink;
}

void StreamSink::build_hello(const DaemonConfig& config, const Model& model,
                             const OutputNames& names) {
  char host[256] = "board";
  gethostname(host, sizeof host - 1);
  strings_.reserve(64);  // views point into these strings: no reallocation after this
  strings_.emplace_back(host);
  strings_.emplace_back(model.metadata().name.empty() ? config.model : std::string(model.metadata().name));
  for (size_t i = 0; i < config.sensors.size(); ++i) {
    const SensorConfig& s = config.sensors[i];
    strings_.push_back(s.name);
    const std::string_view name = strings_.back();
    strings_.push_back(s.sensor_model);
    const std::string_view sensor_model = strings_.back();
    protocol::SensorInfo info;
    info.index = static_cast<uint8_t>(i);
    info.name = name;
    info.model = sensor_model;
    info.serial = "";
    info.pixel_format = image::pixel_format_name(s.format.format);
    info.width = static_cast<uint16_t>(s.format.width);
    info.height = static_cast<uint16_t>(s.format.height);
    info.fps = static_cast<float>(s.fps);
    sensors_.push_back(info);
  }
  label_views_.reserve(names.heads.size());
  for (const OutputNames::Head& h : names.heads) {
    label_views_.emplace_back(h.labels.begin(), h.labels.end());
    protocol::HeadInfo info;
    info.name = h.name;
    info.kind = h.kind == "zero-shot" ? protocol::HeadKind::kZeroShot : protocol::HeadKind::kLinear;
    info.labels = label_views_.back();
    info.accuracy = h.accuracy;  // NaN (protocol::kNotRecorded) when the model has no record
    info.majority_rate = h.majority;
    info.accuracy_ci_low = h.ci_low;
    info.accuracy_ci_high = h.ci_high;
    info.balanced_accuracy = h.balanced;
    info.baseline_accuracy = h.baseline;
    info.groups = h.groups;
    heads_.push_back(info);
  }
  if (!names.grasp_head.empty()) {
    protocol::HeadInfo grasp;
    grasp.name = names.grasp_head;
    grasp.kind = protocol::HeadKind::kGrasp;
    grasp.accuracy = names.grasp.accuracy;
    grasp.majority_rate = names.grasp.majority;
    heads_.push_back(grasp);
  }
  for (const char* s : kStageNames) stage_names_.emplace_back(s);
}

StreamSink::~StreamSink() { close(); }

void StreamSink::close() {
  if (closed_ || sender_ == nullptr) return;
  closed_ = true;
  sender_->stop();  // sends what is queued for up to flush_ms
  const transport::SenderCounters c = sender_->counters();
  TLV_LOG(kLogStream, kInfo, "stream: %llu messages posted, %llu frames sent, dropped %llu (queue full) "
          "%llu (link down) %llu (stale)", static_cast<unsigned long long>(c.posted),
          static_cast<unsigned long long>(c.frames_sent), static_cast<unsigned long long>(c.dropped_queue_full),
          static_cast<unsigned long long>(c.dropped_link_down), static_cast<unsigned long long>(c.dropped_stale));
  // What the flush could not send in time is lost with the process: say so (the frame being
  // written at the deadline has left the queue and is not counted).
  if (c.queue_messages > 0) {
    TLV_LOG(kLogStream, kWarning, "stream: %u queued messages not sent at stop (the link did not take them within "
            "the flush time)", c.queue_messages);
  }
}

void StreamSink::record(const OutputRecord& record, int64_t) {
  Status st;
  if (const auto* p = std::get_if<pipeline::FramePrediction>(&record)) {
    const pipeline::FrameTimes& t = p->times;
    stage_ns_ = {span_ns(t.capture_ns, t.dequeued_ns),     span_ns(t.dequeued_ns, t.decoded_ns),
                 span_ns(t.decoded_ns, t.gated_ns),        span_ns(t.gated_ns, t.preprocessed_ns),
                 span_ns(t.preprocessed_ns, t.inferred_ns), span_ns(t.inferred_ns, t.heads_ns)};
    for (int32_t k = 0; k < p->head_count; ++k) {
      const pipeline::HeadProbabilities& h = p->heads[static_cast<size_t>(k)];
      head_outputs_[static_cast<size_t>(k)] = {static_cast<uint16_t>(h.head),
                                               std::span<const float>(h.probability.data(), static_cast<size_t>(h.labels))};
    }
    protocol::FramePrediction m;
    m.sensor = static_cast<uint8_t>(p->sensor);
    m.frame_sequence = static_cast<uint32_t>(p->sequence);
    m.timing = {t.capture_ns, t.gated_ns, t.heads_ns};
    m.stage_ns = std::span<const uint32_t>(stage_ns_.data(), kStageNames.size());
    m.contact = p->contact_state == 2;
    m.heads = std::span<const protocol::HeadOutput>(head_outputs_.data(),
                                                    p->encoder_ran ? static_cast<size_t>(p->head_count) : 0);
    m.embedding = std::span<const float>(p->embedding.data(), static_cast<size_t>(p->embedding_dim));
    st = sender_->post(m);
  } else if (const auto* g = std::get_if<pipeline::GraspPrediction>(&record)) {
    for (int32_t i = 0; i < g->frame_count; ++i) {
      const pipeline::GraspFrameRef& f = g->frames[static_cast<size_t>(i)];
      grasp_frames_[static_cast<size_t>(i)] = {
          static_cast<uint8_t>(f.finger),
          f.moment == static_cast<uint8_t>(heads::Moment::kBefore) ? protocol::GraspPhase::kBefore
                                                                   : protocol::GraspPhase::kDuring,
          static_cast<uint32_t>(f.sequence), f.capture_ns};
    }
    protocol::GraspPrediction m;
    m.grasp_id = static_cast<uint32_t>(g->grasp_id);
    m.status = g->computed ? protocol::GraspStatus::kComputed : protocol::GraspStatus::kNotComputed;
    if (g->computed) m.probability = g->probability;
    m.reason = g->computed ? protocol::GraspReason::kNone : protocol::GraspReason::kOther;
    m.reason_text = g->reason.data();
    m.frames = std::span<const protocol::GraspFrame>(grasp_frames_.data(), static_cast<size_t>(g->frame_count));
    // Detected grasps say so (an absent phase_source reads as its default, "command").
    m.phase_source = detected_ ? protocol::PhaseSource::kDetected : protocol::PhaseSource::kCommand;
    m.closed_ns = g->started_ns;
    m.infer_end_ns = g->decided_ns;  // on frame time: the capture time that decided it (spec §7)
    st = sender_->post(m);
  } else {
    const EventRecord& e = std::get<EventRecord>(record);
    protocol::ErrorReport m;
    m.code = e.error ? static_cast<uint16_t>(ErrorCode::kCapture) : 0;
    m.name = e.error ? "error" : "info";
    m.text = e.text.data();
    m.sensor = e.sensor < 0 ? protocol::kNoSensor : static_cast<uint8_t>(e.sensor);
    st = sender_->post(m);
  }
  failed_ += st.ok() ? 0 : 1;
}

void StreamSink::stats(const RunTotals& r, bool) {
  for (int32_t i = 0; i < r.sensors; ++i) {
    const auto k = static_cast<size_t>(i);
    sensor_stats_[k] = {static_cast<uint8_t>(i), static_cast<float>(r.sensor_fps[k]),
                        r.sensor_frames[k], r.sensor_encoded[k], r.sensor_gated[k]};
  }
  size_t n = 0;
  drops_[n++] = {protocol::DropCause::kCaptureGap, r.drops_sequence, protocol::kNoSensor};
  drops_[n++] = {protocol::DropCause::kCaptureError, r.bad_frames + r.decode_errors, protocol::kNoSensor};
  // Camera frames skipped for a newer one (the capture thread busy) and decoded frames dropped
  // (inference behind) are both inference_busy; the stream's "stale" is the Sender's (messages
  // too old to send), and its queue_full is added to this output queue's (one entry a cause).
  drops_[n++] = {protocol::DropCause::kInferenceBusy, r.drops_stale + r.drops_queue, protocol::kNoSensor};
  drops_[n++] = {protocol::DropCause::kQueueFull, r.drops_output, protocol::kNoSensor};
  protocol::Stats m;
  m.uptime_ns = static_cast<int64_t>(r.seconds * 1e9);
  m.sensors = std::span<const protocol::SensorStats>(sensor_stats_.data(), static_cast<size_t>(r.sensors));
  m.drops = std::span<const protocol::DropCount>(drops_.data(), n);
  m.cpu_percent = static_cast<float>(r.process_cpu_pct);
  m.cpu_cores = static_cast<uint8_t>(sysconf(_SC_NPROCESSORS_ONLN));
  m.rss_bytes = static_cast<uint64_t>(r.peak_rss_kb) * 1024;
  failed_ += sender_->post(m).ok() ? 0 : 1;
}

}  // namespace tlvlink::daemon::internal
