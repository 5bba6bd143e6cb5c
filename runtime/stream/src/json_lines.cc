#include "tlvlink/stream/json_lines.h"

#include <cinttypes>

#include "tlvlink/protocol/names.h"

namespace tlvlink::stream {
namespace {

// An enum by name, or its number when this build does not know it (a newer board).
template <typename E>
void enum_value(LineBuffer& out, E v, const char* (*name)(E)) {
  if (const char* n = name(v)) {
    out.json_string(n);
  } else {
    out.printf("%u", static_cast<unsigned>(v));
  }
}

void hex64(LineBuffer& out, uint64_t v) { out.printf("\"%016" PRIx64 "\"", v); }
void boolean(LineBuffer& out, bool v) { out.append(v ? "true" : "false"); }

template <typename T>
void unsigned_list(LineBuffer& out, std::span<const T> values) {
  out.put('[');
  for (size_t i = 0; i < values.size(); ++i)
    out.printf("%s%" PRIu64, i ? "," : "", static_cast<uint64_t>(values[i]));
  out.put(']');
}

void float_list(LineBuffer& out, std::span<const float> values) {
  out.put('[');
  for (size_t i = 0; i < values.size(); ++i) {
    if (i) out.put(',');
    out.json_number(values[i]);
  }
  out.put(']');
}

void string_list(LineBuffer& out, std::span<const std::string_view> values) {
  out.put('[');
  for (size_t i = 0; i < values.size(); ++i) {
    if (i) out.put(',');
    out.json_string(values[i]);
  }
  out.put(']');
}

}  // namespace

void json_begin(LineBuffer& out, protocol::MessageType type, const JsonHeader& h) {
  out.append("{\"type\":");
  enum_value(out, type, protocol::message_type_name);
  out.printf(",\"sequence\":%" PRIu32 ",\"flags\":%u,\"delayed\":%s,\"send_ns\":%" PRId64,
             h.sequence, static_cast<unsigned>(h.flags),
             (h.flags & protocol::kFlagDelayed) != 0 ? "true" : "false", h.send_ns);
}

void json_end(LineBuffer& out) { out.append("}\n"); }

void json_fields(LineBuffer& out, const protocol::Hello& m, uint64_t schema_hash) {
  out.key("device"), out.json_string(m.device);
  out.key("board"), out.json_string(m.board);
  out.key("firmware_version"), out.json_string(m.firmware_version);
  out.key("boot_id"), hex64(out, m.boot_id);
  out.key("schema_hash"), hex64(out, schema_hash);
  out.key("schema_matches"), boolean(out, schema_hash == protocol::schema_hash());
  out.key("model_id"), out.json_string(m.model_id);
  out.key("model_checksum"), hex64(out, m.model_checksum);
  out.append(",\"sensors\":[");
  for (size_t i = 0; i < m.sensors.size(); ++i) {
    const protocol::SensorInfo& s = m.sensors[i];
    out.printf("%s{\"index\":%u,\"name\":", i ? "," : "", s.index);
    out.json_string(s.name);
    out.key("model"), out.json_string(s.model);
    out.key("serial"), out.json_string(s.serial);
    out.key("pixel_format"), out.json_string(s.pixel_format);
    out.printf(",\"width\":%u,\"height\":%u,\"fps\":", s.width, s.height);
    out.json_number(s.fps);
    out.put('}');
  }
  out.append("],\"heads\":[");
  for (size_t i = 0; i < m.heads.size(); ++i) {
    const protocol::HeadInfo& h = m.heads[i];
    out.append(i ? ",{\"name\":" : "{\"name\":");
    out.json_string(h.name);
    out.key("kind"), enum_value(out, h.kind, protocol::head_kind_name);
    out.key("labels"), string_list(out, h.labels);
    out.key("accuracy"), out.json_number(h.accuracy);
    out.key("majority_rate"), out.json_number(h.majority_rate);
    out.key("accuracy_ci95"), out.put('[');
    out.json_number(h.accuracy_ci_low);
    out.put(',');
    out.json_number(h.accuracy_ci_high);
    out.put(']');
    out.key("balanced_accuracy"), out.json_number(h.balanced_accuracy);
    out.key("baseline_accuracy"), out.json_number(h.baseline_accuracy);
    out.printf(",\"groups\":%" PRIu32 "}", h.groups);
  }
  out.append("],\"stage_names\":");
  string_list(out, m.stage_names);
  out.printf(",\"embedding_dim\":%u", m.embedding_dim);
  out.key("clock"), out.json_string(m.clock);
  out.printf(",\"max_frame_size\":%" PRIu32, m.max_frame_size);
}

void json_fields(LineBuffer& out, const protocol::FramePrediction& m,
                 const protocol::Hello* names) {
  out.printf(",\"sensor\":%u", m.sensor);
  if (names != nullptr) {
    for (const protocol::SensorInfo& s : names->sensors) {
      if (s.index != m.sensor || s.name.empty()) continue;
      out.key("sensor_name"), out.json_string(s.name);
      break;
    }
  }
  out.printf(",\"frame_sequence\":%" PRIu32 ",\"capture_ns\":%" PRId64
             ",\"infer_start_ns\":%" PRId64 ",\"infer_end_ns\":%" PRId64,
             m.frame_sequence, m.timing.capture_ns, m.timing.infer_start_ns, m.timing.infer_end_ns);
  out.key("stage_ns"), unsigned_list(out, m.stage_ns);
  out.key("contact"), boolean(out, m.contact);
  out.key("gate"), enum_value(out, m.gate, protocol::gate_state_name);
  out.key("gate_score_dn"), out.json_number(m.gate_score_dn);
  out.append(",\"heads\":[");
  for (size_t i = 0; i < m.heads.size(); ++i) {
    const protocol::HeadOutput& h = m.heads[i];
    out.printf("%s{\"head\":%u", i ? "," : "", h.head);
    const protocol::HeadInfo* info =
        names != nullptr && h.head < names->heads.size() ? &names->heads[h.head] : nullptr;
    if (info != nullptr) out.key("name"), out.json_string(info->name);
    out.key("probabilities"), float_list(out, h.probabilities);
    if (!h.probabilities.empty()) {
      size_t top = 0;  // the first of equal maxima
      for (size_t k = 1; k < h.probabilities.size(); ++k) {
        if (h.probabilities[k] > h.probabilities[top]) top = k;
      }
      if (info != nullptr && top < info->labels.size())
        out.key("top_label"), out.json_string(info->labels[top]);
      out.key("top_probability"), out.json_number(h.probabilities[top]);
    }
    out.put('}');
  }
  out.put(']');
  if (!m.embedding.empty()) out.key("embedding"), float_list(out, m.embedding);
}

void json_fields(LineBuffer& out, const protocol::GraspPrediction& m) {
  out.printf(",\"grasp_id\":%" PRIu32, m.grasp_id);
  out.key("status"), enum_value(out, m.status, protocol::grasp_status_name);
  out.key("probability"), out.json_number(m.probability);
  out.key("reason"), enum_value(out, m.reason, protocol::grasp_reason_name);
  out.key("reason_text"), out.json_string(m.reason_text);
  out.append(",\"frames\":[");
  for (size_t i = 0; i < m.frames.size(); ++i) {
    const protocol::GraspFrame& f = m.frames[i];
    out.printf("%s{\"sensor\":%u,\"phase\":", i ? "," : "", f.sensor);
    enum_value(out, f.phase, protocol::grasp_phase_name);
    out.printf(",\"frame_sequence\":%" PRIu32 ",\"capture_ns\":%" PRId64 "}", f.frame_sequence,
               f.capture_ns);
  }
  out.put(']');
  out.key("phase_source"), enum_value(out, m.phase_source, protocol::phase_source_name);
  out.printf(",\"closed_ns\":%" PRId64 ",\"lifting_ns\":%" PRId64 ",\"infer_end_ns\":%" PRId64,
             m.closed_ns, m.lifting_ns, m.infer_end_ns);
}

void json_fields(LineBuffer& out, const protocol::Stats& m) {
  out.printf(",\"uptime_ns\":%" PRId64 ",\"sensors\":[", m.uptime_ns);
  for (size_t i = 0; i < m.sensors.size(); ++i) {
    const protocol::SensorStats& s = m.sensors[i];
    out.printf("%s{\"sensor\":%u,\"fps\":", i ? "," : "", s.sensor);
    out.json_number(s.fps);
    out.printf(",\"frames\":%" PRIu64 ",\"inferred\":%" PRIu64 ",\"gated\":%" PRIu64 "}", s.frames,
               s.inferred, s.gated);
  }
  out.append("],\"drops\":[");
  for (size_t i = 0; i < m.drops.size(); ++i) {
    const protocol::DropCount& d = m.drops[i];
    out.append(i ? ",{\"cause\":" : "{\"cause\":");
    enum_value(out, d.cause, protocol::drop_cause_name);
    out.printf(",\"count\":%" PRIu64 ",\"sensor\":%u}", d.count, d.sensor);
  }
  out.put(']');
  out.key("cpu_percent"), out.json_number(m.cpu_percent);
  out.printf(",\"cpu_cores\":%u,\"rss_bytes\":%" PRIu64, m.cpu_cores, m.rss_bytes);
  const protocol::LinkStats& l = m.link;
  out.printf(",\"link\":{\"link_up\":%s,\"reconnects\":%" PRIu32 ",\"frames_sent\":%" PRIu64
             ",\"bytes_sent\":%" PRIu64 ",\"frames_received\":%" PRIu64
             ",\"frames_rejected\":%" PRIu64 ",\"queue_messages\":%" PRIu32
             ",\"queue_bytes\":%" PRIu32 ",\"queue_capacity_bytes\":%" PRIu32 "}",
             l.link_up ? "true" : "false", l.reconnects, l.frames_sent, l.bytes_sent,
             l.frames_received, l.frames_rejected, l.queue_messages, l.queue_bytes,
             l.queue_capacity_bytes);
}

void json_fields(LineBuffer& out, const protocol::ErrorReport& m) {
  out.printf(",\"code\":%u", m.code);
  out.key("name"), out.json_string(m.name);
  out.key("text"), out.json_string(m.text);
  out.printf(",\"sensor\":%u", m.sensor);
}

void json_fields(LineBuffer& out, const protocol::Ack& m) {
  out.printf(",\"command_sequence\":%" PRIu32, m.command_sequence);
  out.key("kind"), enum_value(out, m.kind, protocol::command_kind_name);
}

void json_fields(LineBuffer& out, const protocol::Nack& m) {
  out.printf(",\"command_sequence\":%" PRIu32, m.command_sequence);
  out.key("kind"), enum_value(out, m.kind, protocol::command_kind_name);
  out.printf(",\"code\":%u", m.code);
  out.key("text"), out.json_string(m.text);
}

void json_fields(LineBuffer& out, const protocol::Pong& m) {
  out.printf(",\"command_sequence\":%" PRIu32 ",\"host_send_ns\":%" PRId64
             ",\"board_receive_ns\":%" PRId64,
             m.command_sequence, m.host_send_ns, m.board_receive_ns);
}

}  // namespace tlvlink::stream
