// One JSON object per message (format.h). The keys are the Python client's Message.to_dict()
// keys; tools/listen/README.md lists them.
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "tlvlink/listen/format.h"
#include "tlvlink/protocol/names.h"

namespace tlvlink::listen {
namespace {

using nlohmann::ordered_json;

ordered_json number_or_null(float v) {
  return std::isnan(v) ? ordered_json(nullptr) : ordered_json(v);
}

std::string hex64(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof(buf), "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

// An enum by name, or its number when this build does not know it (a newer board).
template <typename E>
ordered_json enum_json(E v, const char* (*name)(E)) {
  const char* n = name(v);
  return n ? ordered_json(n) : ordered_json(static_cast<unsigned>(v));
}

std::string_view sensor_name(const FormatContext& c, uint8_t sensor) {
  if (!c.hello) return {};
  Result<protocol::HelloView> h = c.hello->hello();
  if (!h.ok()) return {};
  for (size_t i = 0; i < h.value().sensor_count(); ++i) {
    if (h.value().sensor(i).index == sensor) return h.value().sensor(i).name;
  }
  return {};
}

void hello_json(const protocol::HelloView& h, ordered_json& j) {
  j["device"] = h.device();
  j["board"] = h.board();
  j["firmware_version"] = h.firmware_version();
  j["boot_id"] = hex64(h.boot_id());
  j["schema_hash"] = hex64(h.schema_hash());
  j["schema_matches"] = h.schema_hash() == protocol::schema_hash();
  j["model_id"] = h.model_id();
  j["model_checksum"] = hex64(h.model_checksum());
  ordered_json sensors = ordered_json::array();
  for (size_t i = 0; i < h.sensor_count(); ++i) {
    const protocol::SensorInfo s = h.sensor(i);
    sensors.push_back({{"index", s.index},
                       {"name", s.name},
                       {"model", s.model},
                       {"serial", s.serial},
                       {"pixel_format", s.pixel_format},
                       {"width", s.width},
                       {"height", s.height},
                       {"fps", s.fps}});
  }
  j["sensors"] = sensors;
  ordered_json heads = ordered_json::array();
  for (size_t i = 0; i < h.head_count(); ++i) {
    const protocol::HeadInfoView v = h.head(i);
    ordered_json labels = ordered_json::array();
    for (size_t k = 0; k < v.label_count(); ++k) labels.push_back(v.label(k));
    heads.push_back({{"name", v.name()},
                     {"kind", enum_json(v.kind(), protocol::head_kind_name)},
                     {"labels", labels},
                     {"accuracy", number_or_null(v.accuracy())},
                     {"majority_rate", number_or_null(v.majority_rate())},
                     {"accuracy_ci95",
                      {number_or_null(v.accuracy_ci_low()), number_or_null(v.accuracy_ci_high())}},
                     {"balanced_accuracy", number_or_null(v.balanced_accuracy())},
                     {"baseline_accuracy", number_or_null(v.baseline_accuracy())},
                     {"groups", v.groups()}});
  }
  j["heads"] = heads;
  ordered_json stages = ordered_json::array();
  for (size_t i = 0; i < h.stage_name_count(); ++i) stages.push_back(h.stage_name(i));
  j["stage_names"] = stages;
  j["embedding_dim"] = h.embedding_dim();
  j["clock"] = h.clock();
  j["max_frame_size"] = h.max_frame_size();
}

void frame_json(const Message& m, const protocol::FramePredictionView& f, const FormatContext& c,
                ordered_json& j) {
  j["sensor"] = f.sensor();
  const std::string_view name = sensor_name(c, f.sensor());
  if (!name.empty()) j["sensor_name"] = name;
  j["frame_sequence"] = f.frame_sequence();
  const protocol::FrameTiming t = f.timing();
  j["capture_ns"] = t.capture_ns;
  j["infer_start_ns"] = t.infer_start_ns;
  j["infer_end_ns"] = t.infer_end_ns;
  if (m.clock().valid) j["capture_host_ns"] = m.to_host_ns(t.capture_ns);
  j["stage_ns"] = std::vector<uint32_t>(f.stage_ns().begin(), f.stage_ns().end());
  j["contact"] = f.contact();
  Result<protocol::HelloView> hello =
      c.hello ? c.hello->hello() : Result<protocol::HelloView>(Error(ErrorCode::kInvalidState, ""));
  ordered_json heads = ordered_json::array();
  for (size_t i = 0; i < f.head_count(); ++i) {
    const protocol::HeadOutput h = f.head(i);
    ordered_json o;
    o["head"] = h.head;
    const bool named = hello.ok() && h.head < hello.value().head_count();
    if (named) o["name"] = hello.value().head(h.head).name();
    o["probabilities"] = std::vector<float>(h.probabilities.begin(), h.probabilities.end());
    if (!h.probabilities.empty()) {
      size_t top = 0;
      for (size_t k = 1; k < h.probabilities.size(); ++k) {
        if (h.probabilities[k] > h.probabilities[top]) top = k;
      }
      if (named && top < hello.value().head(h.head).label_count())
        o["top_label"] = hello.value().head(h.head).label(top);
      o["top_probability"] = h.probabilities[top];
    }
    heads.push_back(o);
  }
  j["heads"] = heads;
  if (!f.embedding().empty())
    j["embedding"] = std::vector<float>(f.embedding().begin(), f.embedding().end());
}

void grasp_json(const protocol::GraspPredictionView& g, ordered_json& j) {
  j["grasp_id"] = g.grasp_id();
  j["status"] = enum_json(g.status(), protocol::grasp_status_name);
  j["probability"] = number_or_null(g.probability());
  j["reason"] = enum_json(g.reason(), protocol::grasp_reason_name);
  j["reason_text"] = g.reason_text();
  ordered_json frames = ordered_json::array();
  for (size_t i = 0; i < g.frame_count(); ++i) {
    const protocol::GraspFrame f = g.frame(i);
    frames.push_back({{"sensor", f.sensor},
                      {"phase", enum_json(f.phase, protocol::grasp_phase_name)},
                      {"frame_sequence", f.frame_sequence},
                      {"capture_ns", f.capture_ns}});
  }
  j["frames"] = frames;
  j["phase_source"] = enum_json(g.phase_source(), protocol::phase_source_name);
  j["closed_ns"] = g.closed_ns();
  j["lifting_ns"] = g.lifting_ns();
  j["infer_end_ns"] = g.infer_end_ns();
}

void stats_message_json(const protocol::StatsView& s, ordered_json& j) {
  j["uptime_ns"] = s.uptime_ns();
  ordered_json sensors = ordered_json::array();
  for (size_t i = 0; i < s.sensor_count(); ++i) {
    const protocol::SensorStats x = s.sensor(i);
    sensors.push_back({{"sensor", x.sensor},
                       {"fps", x.fps},
                       {"frames", x.frames},
                       {"inferred", x.inferred},
                       {"gated", x.gated}});
  }
  j["sensors"] = sensors;
  ordered_json drops = ordered_json::array();
  for (size_t i = 0; i < s.drop_count(); ++i) {
    const protocol::DropCount d = s.drop(i);
    drops.push_back({{"cause", enum_json(d.cause, protocol::drop_cause_name)},
                     {"count", d.count},
                     {"sensor", d.sensor}});
  }
  j["drops"] = drops;
  j["cpu_percent"] = number_or_null(s.cpu_percent());
  j["cpu_cores"] = s.cpu_cores();
  j["rss_bytes"] = s.rss_bytes();
  const protocol::LinkStats l = s.link();
  j["link"] = {{"link_up", l.link_up},
               {"reconnects", l.reconnects},
               {"frames_sent", l.frames_sent},
               {"bytes_sent", l.bytes_sent},
               {"frames_received", l.frames_received},
               {"frames_rejected", l.frames_rejected},
               {"queue_messages", l.queue_messages},
               {"queue_bytes", l.queue_bytes},
               {"queue_capacity_bytes", l.queue_capacity_bytes}};
}

std::string base64(std::span<const uint8_t> bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = (uint32_t{bytes[i]} << 16) |
                       (i + 1 < bytes.size() ? uint32_t{bytes[i + 1]} << 8 : 0) |
                       (i + 2 < bytes.size() ? uint32_t{bytes[i + 2]} : 0);
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[n & 63] : '=';
  }
  return out;
}

// The mask as one string of '0'/'1' per row of cells: readable in a JSON line, and the same in
// every language.
void frame_image_json(const Message& m, const protocol::FrameImage& f, const FormatContext& c,
                      ordered_json& j) {
  j["sensor"] = f.sensor;
  const std::string_view name = sensor_name(c, f.sensor);
  if (!name.empty()) j["sensor_name"] = name;
  j["frame_sequence"] = f.frame_sequence;
  j["capture_ns"] = f.capture_ns;
  if (m.clock().valid) j["capture_host_ns"] = m.to_host_ns(f.capture_ns);
  j["kind"] = enum_json(f.kind, protocol::image_kind_name);
  j["width"] = f.width;
  j["height"] = f.height;
  j["format"] = enum_json(f.format, protocol::image_format_name);
  j["contact"] = f.contact;
  j["mask_width"] = f.mask_width;
  j["mask_height"] = f.mask_height;
  ordered_json rows = ordered_json::array();
  for (int y = 0; y < f.mask_height; ++y) {
    std::string row(f.mask_width, '0');
    for (int x = 0; x < f.mask_width; ++x) {
      if (protocol::mask_cell(f.mask, f.mask_width, x, y)) row[static_cast<size_t>(x)] = '1';
    }
    rows.push_back(row);
  }
  j["mask"] = rows;
  j["data"] = base64(f.data);
}

}  // namespace

std::string json_line(const Message& m, const FormatContext& c) {
  ordered_json j;
  j["type"] = enum_json(m.type(), protocol::message_type_name);
  j["sequence"] = m.sequence();
  j["flags"] = m.header().flags;
  j["delayed"] = m.delayed();
  j["send_ns"] = m.send_ns();
  j["receive_ns"] = m.receive_ns();
  if (m.clock().valid) j["send_host_ns"] = m.to_host_ns(m.send_ns());
  switch (m.type()) {
    case protocol::MessageType::kHello:
      if (auto h = m.hello(); h.ok()) hello_json(h.value(), j);
      break;
    case protocol::MessageType::kFramePrediction:
      if (auto f = m.frame_prediction(); f.ok()) frame_json(m, f.value(), c, j);
      break;
    case protocol::MessageType::kGraspPrediction:
      if (auto g = m.grasp_prediction(); g.ok()) grasp_json(g.value(), j);
      break;
    case protocol::MessageType::kStats:
      if (auto s = m.stats(); s.ok()) stats_message_json(s.value(), j);
      break;
    case protocol::MessageType::kError:
      if (auto e = m.error_report(); e.ok()) {
        j["code"] = e.value().code, j["name"] = e.value().name, j["text"] = e.value().text,
        j["sensor"] = e.value().sensor;
      }
      break;
    case protocol::MessageType::kAck:
      if (auto a = m.ack(); a.ok()) {
        j["command_sequence"] = a.value().command_sequence;
        j["kind"] = enum_json(a.value().kind, protocol::command_kind_name);
      }
      break;
    case protocol::MessageType::kNack:
      if (auto n = m.nack(); n.ok()) {
        j["command_sequence"] = n.value().command_sequence;
        j["kind"] = enum_json(n.value().kind, protocol::command_kind_name);
        j["code"] = n.value().code, j["text"] = n.value().text;
      }
      break;
    case protocol::MessageType::kPong:
      if (auto p = m.pong(); p.ok()) {
        j["command_sequence"] = p.value().command_sequence;
        j["host_send_ns"] = p.value().host_send_ns;
        j["board_receive_ns"] = p.value().board_receive_ns;
        j["round_trip_ns"] =
            (m.receive_ns() - p.value().host_send_ns) - (m.send_ns() - p.value().board_receive_ns);
      }
      break;
    case protocol::MessageType::kFrameImage:
      if (auto f = m.frame_image(); f.ok()) frame_image_json(m, f.value(), c, j);
      break;
    case protocol::MessageType::kCommand: break;
  }
  // A board's strings are not checked to be UTF-8 (a sensor name, an error text): an invalid
  // byte becomes U+FFFD instead of an exception that would end the listener.
  return j.dump(-1, ' ', false, ordered_json::error_handler_t::replace);
}

std::string stats_json(const LinkStats& s) {
  const protocol::DeframerCounters& f = s.frames;
  ordered_json j;
  j["bytes"] = f.bytes;
  j["frames"] = f.frames;
  j["rejected"] = {{"oversized", f.oversized}, {"cobs", f.cobs},
                   {"truncated", f.truncated}, {"crc", f.crc},
                   {"magic", f.magic},         {"version", f.version},
                   {"length", f.length},       {"flags", f.flags}};
  j["discarded_bytes"] = f.discarded_bytes;
  j["messages"] = s.messages;
  j["unknown_types"] = s.unknown_types;
  j["undecodable"] = s.undecodable;
  j["sequence_gaps"] = s.sequence_gaps;
  j["frames_missing"] = s.frames_missing;
  j["sequence_resets"] = s.sequence_resets;
  j["board_restarts"] = s.board_restarts;
  j["delayed"] = s.delayed;
  j["connects"] = s.connects;
  j["disconnects"] = s.disconnects;
  j["link_up"] = s.link_up;
  auto latency = [](const LatencyWindow& w) {
    return ordered_json{{"count", w.count()},
                        {"p50_ns", w.percentile(50)},
                        {"p99_ns", w.percentile(99)},
                        {"max_ns", w.max()}};
  };
  j["link_latency"] = latency(s.link_latency);
  j["capture_latency"] = latency(s.capture_latency);
  j["round_trip"] = latency(s.round_trip);
  j["clock"] = {{"valid", s.clock.valid},
                {"offset_ns", s.clock.offset_ns},
                {"uncertainty_ns", s.clock.uncertainty_ns}};
  return j.dump();
}

}  // namespace tlvlink::listen
