// The channel table and the mapping of a received message to its channel (channels.h).
#include "tlvlink/foxglove/channels.h"

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "channel_schemas.h"
#include "tlvlink/protocol/messages.h"

namespace tlvlink::foxglove {

using protocol::MessageType;

namespace {

// foxglove.CompressedImage's frame_id: the sensor's name from the Hello, else "sensorN".
void add_frame_id(const listen::Message& m, const listen::FormatContext& context,
                  std::string& json) {
  Result<protocol::FrameImage> f = m.frame_image();
  if (!f.ok()) return;
  std::string id = "sensor" + std::to_string(f.value().sensor);
  if (context.hello) {
    if (auto h = context.hello->hello(); h.ok()) {
      for (size_t i = 0; i < h.value().sensor_count(); ++i) {
        const protocol::SensorInfo s = h.value().sensor(i);
        if (s.index == f.value().sensor && !s.name.empty()) id = std::string(s.name);
      }
    }
  }
  json.pop_back();
  json += ",\"frame_id\":" +
          nlohmann::json(id).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "}";
}

}  // namespace

std::span<const ChannelSpec> channel_table() {
  const internal::ChannelSchemas& s = internal::channel_schemas();
  static const ChannelSpec kTable[] = {
      {1, "/tlvlink/hello", "tlvlink.Hello", s.hello},
      {2, "/tlvlink/frame_prediction", "tlvlink.FramePrediction", s.frame_prediction},
      {3, "/tlvlink/grasp_prediction", "tlvlink.GraspPrediction", s.grasp_prediction},
      {4, "/tlvlink/stats", "tlvlink.Stats", s.stats},
      {5, "/tlvlink/error", "tlvlink.Error", s.error},
      {6, "/tlvlink/ack", "tlvlink.Ack", s.ack},
      {7, "/tlvlink/nack", "tlvlink.Nack", s.nack},
      {8, "/tlvlink/pong", "tlvlink.Pong", s.pong},
      // One topic for every sensor: frame_id names the sensor (Foxglove's Image panel picks one).
      {9, "/tlvlink/frame_image", "foxglove.CompressedImage", s.frame_image},
  };
  return kTable;
}

std::optional<ChannelMessage> to_channel_message(const listen::Message& m,
                                                 const listen::FormatContext& context) {
  uint16_t channel = 0;
  int64_t board_ns = m.send_ns();
  switch (m.type()) {
    case MessageType::kHello: channel = 1; break;
    case MessageType::kFramePrediction:
      channel = 2;
      if (auto f = m.frame_prediction(); f.ok()) board_ns = f.value().timing().capture_ns;
      break;
    case MessageType::kGraspPrediction: channel = 3; break;
    case MessageType::kStats: channel = 4; break;
    case MessageType::kError: channel = 5; break;
    case MessageType::kAck: channel = 6; break;
    case MessageType::kNack: channel = 7; break;
    case MessageType::kPong: channel = 8; break;
    case MessageType::kFrameImage:
      channel = 9;
      if (auto f = m.frame_image(); f.ok()) board_ns = f.value().capture_ns;
      break;
    case MessageType::kCommand: return std::nullopt;
  }
  ChannelMessage out;
  out.channel_id = channel;
  out.publish_time_ns = m.receive_ns();
  out.log_time_ns = m.clock().valid ? m.to_host_ns(board_ns) : m.receive_ns();
  if (out.log_time_ns < 0)
    out.log_time_ns = m.receive_ns();  // a board time before the host's clock origin
  // The listener's JSON line, with one more key: json_line always ends its object with '}'.
  out.json = listen::json_line(m, context);
  char stamp[64];
  std::snprintf(stamp, sizeof(stamp), ",\"timestamp\":{\"sec\":%lld,\"nsec\":%lld}}",
                static_cast<long long>(out.log_time_ns / 1'000'000'000),
                static_cast<long long>(out.log_time_ns % 1'000'000'000));
  out.json.pop_back();
  out.json += stamp;
  if (channel == 9) add_frame_id(m, context, out.json);
  return out;
}

}  // namespace tlvlink::foxglove
