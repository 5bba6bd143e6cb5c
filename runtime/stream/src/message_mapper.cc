#include "tlvlink/stream/message_mapper.h"

#include <algorithm>
#include <limits>
#include <span>

#include "tlvlink/error.h"
#include "tlvlink/heads/grasp_layout.h"

namespace tlvlink::stream {
namespace {

// pipeline::ContactState (calibrating 0, no contact 1, contact 2) on the wire, where 0 is
// "unknown" (a board older than protocol 1.3).
protocol::GateState gate_state(uint8_t contact_state) {
  switch (contact_state) {
    case 0: return protocol::GateState::kCalibrating;
    case 1: return protocol::GateState::kNone;
    case 2: return protocol::GateState::kContact;
    default: return protocol::GateState::kUnknown;
  }
}

uint32_t span_ns(int64_t from, int64_t to) {
  if (from <= 0 || to < from) return 0;
  return static_cast<uint32_t>(std::min<int64_t>(to - from, std::numeric_limits<uint32_t>::max()));
}

}  // namespace

protocol::FramePrediction MessageMapper::frame(const pipeline::FramePrediction& p) {
  const pipeline::FrameTimes& t = p.times;
  stage_ns_ = {span_ns(t.capture_ns, t.dequeued_ns),      span_ns(t.dequeued_ns, t.decoded_ns),
               span_ns(t.decoded_ns, t.gated_ns),         span_ns(t.gated_ns, t.preprocessed_ns),
               span_ns(t.preprocessed_ns, t.inferred_ns), span_ns(t.inferred_ns, t.heads_ns)};
  for (int32_t k = 0; k < p.head_count; ++k) {
    const pipeline::HeadProbabilities& h = p.heads[static_cast<size_t>(k)];
    head_outputs_[static_cast<size_t>(k)] = {
        static_cast<uint16_t>(h.head),
        std::span<const float>(h.probability.data(), static_cast<size_t>(h.labels))};
  }
  protocol::FramePrediction m;
  m.sensor = static_cast<uint8_t>(p.sensor);
  m.frame_sequence = static_cast<uint32_t>(p.sequence);
  m.timing = {t.capture_ns, t.gated_ns, t.heads_ns};
  m.stage_ns = std::span<const uint32_t>(stage_ns_.data(), stage_ns_.size());
  m.contact = p.contact_state == 2;
  m.heads = std::span<const protocol::HeadOutput>(
      head_outputs_.data(), p.encoder_ran ? static_cast<size_t>(p.head_count) : 0);
  m.embedding = std::span<const float>(p.embedding.data(), static_cast<size_t>(p.embedding_dim));
  m.gate = gate_state(p.contact_state);
  m.gate_score_dn = p.contact_score_dn;
  return m;
}

protocol::GraspPrediction MessageMapper::grasp(const pipeline::GraspPrediction& g) {
  for (int32_t i = 0; i < g.frame_count; ++i) {
    const pipeline::GraspFrameRef& f = g.frames[static_cast<size_t>(i)];
    grasp_frames_[static_cast<size_t>(i)] = {
        static_cast<uint8_t>(f.finger),
        f.moment == static_cast<uint8_t>(heads::Moment::kBefore) ? protocol::GraspPhase::kBefore
                                                                 : protocol::GraspPhase::kDuring,
        static_cast<uint32_t>(f.sequence), f.capture_ns};
  }
  protocol::GraspPrediction m;
  m.grasp_id = static_cast<uint32_t>(g.grasp_id);
  m.status = g.computed ? protocol::GraspStatus::kComputed : protocol::GraspStatus::kNotComputed;
  if (g.computed) m.probability = g.probability;
  m.reason = g.computed ? protocol::GraspReason::kNone : protocol::GraspReason::kOther;
  m.reason_text = g.reason.data();
  m.frames = std::span<const protocol::GraspFrame>(grasp_frames_.data(),
                                                   static_cast<size_t>(g.frame_count));
  // Detected grasps say so (an absent phase_source reads as its default, "command").
  m.phase_source = detected_ ? protocol::PhaseSource::kDetected : protocol::PhaseSource::kCommand;
  m.closed_ns = g.started_ns;
  m.infer_end_ns = g.decided_ns;  // on frame time: the capture time that decided it (spec §7)
  return m;
}

protocol::ErrorReport MessageMapper::event(bool error, int32_t sensor, const char* text) {
  protocol::ErrorReport m;
  m.code = error ? static_cast<uint16_t>(ErrorCode::kCapture) : 0;
  m.name = error ? "error" : "info";
  m.text = text;
  m.sensor = sensor < 0 ? protocol::kNoSensor : static_cast<uint8_t>(sensor);
  return m;
}

protocol::FrameImage MessageMapper::image(const FrameImageRecord& r) {
  protocol::FrameImage m;
  m.sensor = static_cast<uint8_t>(r.sensor);
  m.frame_sequence = static_cast<uint32_t>(r.sequence);
  m.capture_ns = r.capture_ns;
  m.kind = r.input ? protocol::ImageKind::kInput : protocol::ImageKind::kView;
  m.width = static_cast<uint16_t>(r.width);
  m.height = static_cast<uint16_t>(r.height);
  m.format = protocol::ImageFormat::kJpeg;
  m.contact = r.contact;
  m.mask_width = static_cast<uint8_t>(r.mask_width);
  m.mask_height = static_cast<uint8_t>(r.mask_height);
  m.mask = r.mask;
  m.data = r.jpeg;
  return m;
}

protocol::Stats MessageMapper::stats(const StreamTotals& t) {
  for (int32_t i = 0; i < t.sensors; ++i) {
    const auto k = static_cast<size_t>(i);
    sensor_stats_[k] = {static_cast<uint8_t>(i), static_cast<float>(t.sensor_fps[k]),
                        t.sensor_frames[k], t.sensor_encoded[k], t.sensor_gated[k]};
  }
  // One entry a cause; the link's own drops (link_down, stale, its queue_full) are the Sender's.
  drops_ = {
      protocol::DropCount{protocol::DropCause::kCaptureGap, t.capture_gap, protocol::kNoSensor},
      protocol::DropCount{protocol::DropCause::kCaptureError, t.capture_error, protocol::kNoSensor},
      protocol::DropCount{protocol::DropCause::kInferenceBusy, t.inference_busy,
                          protocol::kNoSensor},
      protocol::DropCount{protocol::DropCause::kQueueFull, t.queue_full, protocol::kNoSensor},
      protocol::DropCount{protocol::DropCause::kImageBusy, t.image_busy, protocol::kNoSensor}};
  protocol::Stats m;
  m.uptime_ns = static_cast<int64_t>(t.seconds * 1e9);
  m.sensors =
      std::span<const protocol::SensorStats>(sensor_stats_.data(), static_cast<size_t>(t.sensors));
  // image_busy only from a board that sends images (a 1.1 host would print an unknown cause).
  m.drops =
      std::span<const protocol::DropCount>(drops_.data(), drops_.size() - (t.frame_images ? 0 : 1));
  m.cpu_percent = static_cast<float>(t.cpu_percent);
  m.cpu_cores = t.cpu_cores;
  m.rss_bytes = t.rss_bytes;
  return m;
}

}  // namespace tlvlink::stream
