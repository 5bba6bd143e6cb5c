// One JSON object per message (format.h): the message's keys written by the stream's shared
// JSON-lines writer (runtime/stream json_lines.h, the same code as a board's `jsonl:` output),
// then the keys only a host has (receive time, host-clock times once the clock is known, the
// round trip); tools/listen/README.md lists them.
#include <nlohmann/json.hpp>

#include <optional>
#include <vector>

#include "message_copy.h"
#include "tlvlink/listen/format.h"
#include "tlvlink/protocol/names.h"
#include "tlvlink/stream/json_lines.h"

namespace tlvlink::listen {
namespace {

using nlohmann::ordered_json;
using stream::LineBuffer;

void base64(LineBuffer& out, std::span<const uint8_t> bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  out.put('"');
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = (uint32_t{bytes[i]} << 16) |
                       (i + 1 < bytes.size() ? uint32_t{bytes[i + 1]} << 8 : 0) |
                       (i + 2 < bytes.size() ? uint32_t{bytes[i + 2]} : 0);
    out.put(kAlphabet[(n >> 18) & 63]);
    out.put(kAlphabet[(n >> 12) & 63]);
    out.put(i + 1 < bytes.size() ? kAlphabet[(n >> 6) & 63] : '=');
    out.put(i + 2 < bytes.size() ? kAlphabet[n & 63] : '=');
  }
  out.put('"');
}

// A FrameImage (no board writes one into JSON lines: its JPEG is larger than a board's line).
// The mask as one string of '0'/'1' per row of cells: readable in a JSON line, and the same in
// every language.
void frame_image_fields(LineBuffer& out, const protocol::FrameImage& f,
                        const protocol::Hello* names) {
  out.printf(",\"sensor\":%u", f.sensor);
  if (names != nullptr) {
    for (const protocol::SensorInfo& s : names->sensors) {
      if (s.index != f.sensor || s.name.empty()) continue;
      out.key("sensor_name"), out.json_string(s.name);
      break;
    }
  }
  out.printf(",\"frame_sequence\":%u,\"capture_ns\":%lld", f.frame_sequence,
             static_cast<long long>(f.capture_ns));
  const char* kind = protocol::image_kind_name(f.kind);
  const char* format = protocol::image_format_name(f.format);
  out.key("kind"), kind ? out.json_string(kind) : out.printf("%u", static_cast<unsigned>(f.kind));
  out.printf(",\"width\":%u,\"height\":%u", f.width, f.height);
  out.key("format");
  format ? out.json_string(format) : out.printf("%u", static_cast<unsigned>(f.format));
  out.printf(",\"contact\":%s,\"mask_width\":%u,\"mask_height\":%u,\"mask\":[",
             f.contact ? "true" : "false", f.mask_width, f.mask_height);
  for (int y = 0; y < f.mask_height; ++y) {
    out.append(y > 0 ? ",\"" : "\"");
    for (int x = 0; x < f.mask_width; ++x)
      out.put(protocol::mask_cell(f.mask, f.mask_width, x, y) ? '1' : '0');
    out.put('"');
  }
  out.append("],\"data\":");
  base64(out, f.data);
}

void write_line(LineBuffer& out, const Message& m, const FormatContext& c) {
  std::optional<internal::HelloCopy> names;
  if (c.hello != nullptr) {
    if (auto h = c.hello->hello(); h.ok()) names.emplace(h.value());
  }
  const protocol::Hello* hello_names = names ? &names->hello : nullptr;
  stream::json_begin(out, m.type(), {m.sequence(), m.header().flags, m.send_ns()});
  std::optional<int64_t> capture_ns;  // a frame's, for its host-clock time
  switch (m.type()) {
    case protocol::MessageType::kHello:
      if (auto h = m.hello(); h.ok()) {
        const internal::HelloCopy copy(h.value());
        stream::json_fields(out, copy.hello, copy.schema_hash);
      }
      break;
    case protocol::MessageType::kFramePrediction:
      if (auto f = m.frame_prediction(); f.ok()) {
        const internal::FrameCopy copy(f.value());
        stream::json_fields(out, copy.frame, hello_names);
        capture_ns = copy.frame.timing.capture_ns;
      }
      break;
    case protocol::MessageType::kGraspPrediction:
      if (auto g = m.grasp_prediction(); g.ok()) {
        stream::json_fields(out, internal::GraspCopy(g.value()).grasp);
      }
      break;
    case protocol::MessageType::kStats:
      if (auto s = m.stats(); s.ok())
        stream::json_fields(out, internal::StatsCopy(s.value()).stats);
      break;
    case protocol::MessageType::kError:
      if (auto e = m.error_report(); e.ok()) stream::json_fields(out, e.value());
      break;
    case protocol::MessageType::kAck:
      if (auto a = m.ack(); a.ok()) stream::json_fields(out, a.value());
      break;
    case protocol::MessageType::kNack:
      if (auto n = m.nack(); n.ok()) stream::json_fields(out, n.value());
      break;
    case protocol::MessageType::kPong:
      if (auto p = m.pong(); p.ok()) {
        stream::json_fields(out, p.value());
        out.printf(",\"round_trip_ns\":%lld",
                   static_cast<long long>((m.receive_ns() - p.value().host_send_ns) -
                                          (m.send_ns() - p.value().board_receive_ns)));
      }
      break;
    case protocol::MessageType::kFrameImage:
      if (auto f = m.frame_image(); f.ok()) {
        frame_image_fields(out, f.value(), hello_names);
        capture_ns = f.value().capture_ns;
      }
      break;
    case protocol::MessageType::kCommand: break;
  }
  // What only the host knows, after the message's own keys.
  out.printf(",\"receive_ns\":%lld", static_cast<long long>(m.receive_ns()));
  if (m.clock().valid) {
    out.printf(",\"send_host_ns\":%lld", static_cast<long long>(m.to_host_ns(m.send_ns())));
    if (capture_ns) {
      out.printf(",\"capture_host_ns\":%lld", static_cast<long long>(m.to_host_ns(*capture_ns)));
    }
  }
  stream::json_end(out);
}

}  // namespace

std::string json_line(const Message& m, const FormatContext& c) {
  // One buffer a thread, kept: a line longer than it (a large FrameImage) is written again into
  // a larger one, never cut.
  thread_local std::vector<char> storage(64 * 1024);
  for (;;) {
    LineBuffer out(storage);
    write_line(out, m, c);
    if (!out.overflowed()) {
      std::string_view v = out.view();
      v.remove_suffix(1);  // the newline: callers print lines
      return std::string(v);
    }
    storage.resize(storage.size() * 4);
  }
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
