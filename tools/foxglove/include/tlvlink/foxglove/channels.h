#pragma once
// The channel table: what a listener publishes to Foxglove (WebSocket server, MCAP recording).
// One channel per message type the stream delivers, message encoding `json`, each with a
// `jsonschema` schema. A message's JSON is the listener's JSON line for it (tools/listen's
// json_line: the same keys, the same values) plus `timestamp` {sec, nsec}: its log time.
//
// Log time: the board time of the message mapped to the host's CLOCK_MONOTONIC with the
// listener's clock estimate (Message::to_host_ns): a frame prediction's capture time, any other
// message's send time; before the first clock estimate (or with --no-time-sync), the host
// receive time. Publish time: the host receive time.
//
// A new channel (the frames of issue 33 item 1: `foxglove.CompressedImage`) is one more row in
// the table and one more case in to_channel_message.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "tlvlink/listen/format.h"
#include "tlvlink/listen/message.h"

namespace tlvlink::foxglove {

struct ChannelSpec {
  uint16_t id;                   // MCAP channel and schema id, Foxglove channel id
  std::string_view topic;        // "/tlvlink/frame_prediction"
  std::string_view schema_name;  // "tlvlink.FramePrediction"
  std::string_view schema;       // JSON Schema text (schema encoding "jsonschema")
};
inline constexpr std::string_view kMessageEncoding = "json";
inline constexpr std::string_view kSchemaEncoding = "jsonschema";

std::span<const ChannelSpec> channel_table();

struct ChannelMessage {
  uint16_t channel_id = 0;
  int64_t log_time_ns = 0;
  int64_t publish_time_ns = 0;
  std::string json;
};

// nullopt for a message type no channel carries (a Command echoed by a peer).
std::optional<ChannelMessage> to_channel_message(const listen::Message& message,
                                                 const listen::FormatContext& context);

}  // namespace tlvlink::foxglove
