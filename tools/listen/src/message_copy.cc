#include "message_copy.h"

namespace tlvlink::listen::internal {

HelloCopy::HelloCopy(const protocol::HelloView& v) : schema_hash(v.schema_hash()) {
  for (size_t i = 0; i < v.sensor_count(); ++i) sensors.push_back(v.sensor(i));
  labels.resize(v.head_count());
  for (size_t i = 0; i < v.head_count(); ++i) {
    const protocol::HeadInfoView h = v.head(i);
    for (size_t k = 0; k < h.label_count(); ++k) labels[i].push_back(h.label(k));
    protocol::HeadInfo info;
    info.name = h.name();
    info.kind = h.kind();
    info.labels = labels[i];
    info.accuracy = h.accuracy();
    info.majority_rate = h.majority_rate();
    info.accuracy_ci_low = h.accuracy_ci_low();
    info.accuracy_ci_high = h.accuracy_ci_high();
    info.balanced_accuracy = h.balanced_accuracy();
    info.baseline_accuracy = h.baseline_accuracy();
    info.groups = h.groups();
    heads.push_back(info);
  }
  for (size_t i = 0; i < v.stage_name_count(); ++i) stages.push_back(v.stage_name(i));
  hello.device = v.device();
  hello.board = v.board();
  hello.firmware_version = v.firmware_version();
  hello.boot_id = v.boot_id();
  hello.model_id = v.model_id();
  hello.model_checksum = v.model_checksum();
  hello.sensors = sensors;
  hello.heads = heads;
  hello.stage_names = stages;
  hello.embedding_dim = v.embedding_dim();
  hello.clock = v.clock();
  hello.max_frame_size = v.max_frame_size();
}

FrameCopy::FrameCopy(const protocol::FramePredictionView& v) {
  for (size_t i = 0; i < v.head_count(); ++i) heads.push_back(v.head(i));
  frame.sensor = v.sensor();
  frame.frame_sequence = v.frame_sequence();
  frame.timing = v.timing();
  frame.stage_ns = v.stage_ns();
  frame.contact = v.contact();
  frame.heads = heads;
  frame.embedding = v.embedding();
  frame.gate = v.gate();
  frame.gate_score_dn = v.gate_score_dn();
}

GraspCopy::GraspCopy(const protocol::GraspPredictionView& v) {
  for (size_t i = 0; i < v.frame_count(); ++i) frames.push_back(v.frame(i));
  grasp.grasp_id = v.grasp_id();
  grasp.status = v.status();
  grasp.probability = v.probability();
  grasp.reason = v.reason();
  grasp.reason_text = v.reason_text();
  grasp.frames = frames;
  grasp.phase_source = v.phase_source();
  grasp.closed_ns = v.closed_ns();
  grasp.lifting_ns = v.lifting_ns();
  grasp.infer_end_ns = v.infer_end_ns();
}

StatsCopy::StatsCopy(const protocol::StatsView& v) {
  for (size_t i = 0; i < v.sensor_count(); ++i) sensors.push_back(v.sensor(i));
  for (size_t i = 0; i < v.drop_count(); ++i) drops.push_back(v.drop(i));
  stats.uptime_ns = v.uptime_ns();
  stats.sensors = sensors;
  stats.drops = drops;
  stats.cpu_percent = v.cpu_percent();
  stats.cpu_cores = v.cpu_cores();
  stats.rss_bytes = v.rss_bytes();
  stats.link = v.link();
}

}  // namespace tlvlink::listen::internal
