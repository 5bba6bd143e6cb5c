// One human-readable line per message, and the link statistics as text (format.h).
#include <cinttypes>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <string>

#include "tlvlink/listen/format.h"
#include "tlvlink/protocol/names.h"

namespace tlvlink::listen {
namespace {

std::string sprintf_string(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string sprintf_string(const char* format, ...) {
  char buf[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buf, sizeof(buf), format, args);
  va_end(args);
  return buf;
}

template <typename E>
std::string name_or_number(E v, const char* (*name)(E)) {
  const char* n = name(v);
  return n ? n : std::to_string(static_cast<unsigned>(v));
}

double ms(int64_t ns) { return static_cast<double>(ns) / 1e6; }

std::string frame_text(const protocol::FramePredictionView& f, const FormatContext& c) {
  Result<protocol::HelloView> h =
      c.hello ? c.hello->hello() : Result<protocol::HelloView>(Error(ErrorCode::kInvalidState, ""));
  // The gate's state (minor 3): a frame it has not decided on yet says so.
  const char* gate = f.gate() == protocol::GateState::kCalibrating ? "calibrating"
                     : f.contact()                                 ? "contact"
                                                                   : "no-contact";
  std::string line = sprintf_string("frame  s%u #%-7u %s", f.sensor(), f.frame_sequence(), gate);
  for (size_t i = 0; i < f.head_count(); ++i) {
    const protocol::HeadOutput o = f.head(i);
    if (o.probabilities.empty()) continue;
    size_t top = 0;
    for (size_t k = 1; k < o.probabilities.size(); ++k) {
      if (o.probabilities[k] > o.probabilities[top]) top = k;
    }
    const bool named = h.ok() && o.head < h.value().head_count();
    const std::string head =
        named ? std::string(h.value().head(o.head).name()) : "head" + std::to_string(o.head);
    const std::string label = named && top < h.value().head(o.head).label_count()
                                  ? std::string(h.value().head(o.head).label(top))
                                  : std::to_string(top);
    line += sprintf_string("  %s=%s(%.2f)", head.c_str(), label.c_str(),
                           static_cast<double>(o.probabilities[top]));
  }
  const protocol::FrameTiming t = f.timing();
  line += sprintf_string("  infer %.2f ms", ms(t.infer_end_ns - t.infer_start_ns));
  if (!f.embedding().empty()) line += sprintf_string("  embedding[%zu]", f.embedding().size());
  return line;
}

}  // namespace

std::string text_line(const Message& m, const FormatContext& c) {
  std::string line;
  switch (m.type()) {
    case protocol::MessageType::kHello:
      if (auto h = m.hello(); h.ok()) {
        const protocol::HelloView& v = h.value();
        line = sprintf_string(
            "hello  %.*s (%.*s, firmware %.*s) model %.*s, %zu sensors, %zu heads%s",
            static_cast<int>(v.device().size()), v.device().data(),
            static_cast<int>(v.board().size()), v.board().data(),
            static_cast<int>(v.firmware_version().size()), v.firmware_version().data(),
            static_cast<int>(v.model_id().size()), v.model_id().data(), v.sensor_count(),
            v.head_count(),
            v.schema_hash() == protocol::schema_hash() ? ""
                                                       : "  [schema differs from this client's]");
      }
      break;
    case protocol::MessageType::kFramePrediction:
      if (auto f = m.frame_prediction(); f.ok()) line = frame_text(f.value(), c);
      break;
    case protocol::MessageType::kGraspPrediction:
      if (auto g = m.grasp_prediction(); g.ok()) {
        const auto& v = g.value();
        if (v.status() == protocol::GraspStatus::kComputed) {
          line =
              sprintf_string("grasp  #%u success p=%.3f from %zu frames (%s phases)", v.grasp_id(),
                             static_cast<double>(v.probability()), v.frame_count(),
                             name_or_number(v.phase_source(), protocol::phase_source_name).c_str());
        } else {
          line = sprintf_string("grasp  #%u not computed: %s%s%.*s", v.grasp_id(),
                                name_or_number(v.reason(), protocol::grasp_reason_name).c_str(),
                                v.reason_text().empty() ? "" : ": ",
                                static_cast<int>(v.reason_text().size()), v.reason_text().data());
        }
      }
      break;
    case protocol::MessageType::kStats:
      if (auto s = m.stats(); s.ok()) {
        const auto& v = s.value();
        line = sprintf_string("stats  up %.1f s", static_cast<double>(v.uptime_ns()) / 1e9);
        for (size_t i = 0; i < v.sensor_count(); ++i) {
          line += sprintf_string("  s%u %.1f fps", v.sensor(i).sensor,
                                 static_cast<double>(v.sensor(i).fps));
        }
        std::string drops;
        for (size_t i = 0; i < v.drop_count(); ++i) {
          if (v.drop(i).count == 0) continue;
          drops += sprintf_string(
              " %s=%" PRIu64, name_or_number(v.drop(i).cause, protocol::drop_cause_name).c_str(),
              v.drop(i).count);
        }
        line += "  drops:" + (drops.empty() ? std::string(" none") : drops);
        if (!std::isnan(v.cpu_percent()))
          line += sprintf_string("  cpu %.0f%%", static_cast<double>(v.cpu_percent()));
        const protocol::LinkStats l = v.link();
        line +=
            sprintf_string("  link %s queue %u msgs", l.link_up ? "up" : "down", l.queue_messages);
      }
      break;
    case protocol::MessageType::kError:
      if (auto e = m.error_report(); e.ok()) {
        line = sprintf_string("error  %.*s: %.*s", static_cast<int>(e.value().name.size()),
                              e.value().name.data(), static_cast<int>(e.value().text.size()),
                              e.value().text.data());
      }
      break;
    case protocol::MessageType::kAck:
      if (auto a = m.ack(); a.ok()) {
        line = sprintf_string("ack    #%u %s", a.value().command_sequence,
                              name_or_number(a.value().kind, protocol::command_kind_name).c_str());
      }
      break;
    case protocol::MessageType::kNack:
      if (auto n = m.nack(); n.ok()) {
        line = sprintf_string("nack   #%u %s: %.*s", n.value().command_sequence,
                              name_or_number(n.value().kind, protocol::command_kind_name).c_str(),
                              static_cast<int>(n.value().text.size()), n.value().text.data());
      }
      break;
    case protocol::MessageType::kPong:
      if (auto p = m.pong(); p.ok()) {
        const int64_t rtt =
            (m.receive_ns() - p.value().host_send_ns) - (m.send_ns() - p.value().board_receive_ns);
        line = sprintf_string("pong   #%u round trip %.3f ms", p.value().command_sequence, ms(rtt));
      }
      break;
    case protocol::MessageType::kFrameImage:
      if (auto r = m.frame_image(); r.ok()) {
        const protocol::FrameImage& f = r.value();
        size_t cells = 0;
        for (uint8_t b : f.mask) cells += static_cast<size_t>(__builtin_popcount(b));
        line = sprintf_string(
            "image  s%u #%-7u %s %ux%u %s %zu B %s, mask %zu/%u cells", f.sensor, f.frame_sequence,
            name_or_number(f.kind, protocol::image_kind_name).c_str(), f.width, f.height,
            name_or_number(f.format, protocol::image_format_name).c_str(), f.data.size(),
            f.contact ? "contact" : "no-contact", cells, unsigned{f.mask_width} * f.mask_height);
      }
      break;
    case protocol::MessageType::kCommand: break;
  }
  if (line.empty())
    line = sprintf_string("?      message type 0x%04x (%zu bytes)", static_cast<unsigned>(m.type()),
                          m.payload().size());
  if (m.delayed()) line += "  [delayed]";
  return line;
}

std::string stats_text(const LinkStats& s) {
  const protocol::DeframerCounters& f = s.frames;
  std::string out =
      sprintf_string("link: %" PRIu64 " bytes, %" PRIu64 " frames, %" PRIu64
                     " rejected (crc %" PRIu64 ", cobs %" PRIu64 ", truncated %" PRIu64
                     ", oversized %" PRIu64 ", magic %" PRIu64 ", version %" PRIu64
                     ", length %" PRIu64 ", flags %" PRIu64 "), %" PRIu64 " bytes discarded\n",
                     f.bytes, f.frames, f.rejected(), f.crc, f.cobs, f.truncated, f.oversized,
                     f.magic, f.version, f.length, f.flags, f.discarded_bytes);
  out +=
      sprintf_string("      sequence gaps %" PRIu64 " (%" PRIu64 " frames missing), resets %" PRIu64
                     ", board restarts %" PRIu64 ", delayed %" PRIu64 ", unknown types %" PRIu64
                     ", undecodable %" PRIu64 ", connects %" PRIu64 ", disconnects %" PRIu64 "\n",
                     s.sequence_gaps, s.frames_missing, s.sequence_resets, s.board_restarts,
                     s.delayed, s.unknown_types, s.undecodable, s.connects, s.disconnects);
  auto latency = [&](const char* what, const LatencyWindow& w) {
    if (w.count() == 0) return sprintf_string("      %s: no samples\n", what);
    return sprintf_string("      %s: p50 %.3f ms, p99 %.3f ms, max %.3f ms (%zu samples)\n", what,
                          ms(w.percentile(50)), ms(w.percentile(99)), ms(w.max()), w.count());
  };
  out += latency("send->receive", s.link_latency);
  out += latency("capture->receive", s.capture_latency);
  out += latency("round trip", s.round_trip);
  if (s.clock.valid) {
    out += sprintf_string("      board clock - host clock = %+.3f ms +- %.3f ms\n",
                          ms(s.clock.offset_ns), ms(s.clock.uncertainty_ns));
  }
  return out;
}

}  // namespace tlvlink::listen
