#pragma once
// The JSON Schemas of the channel table (channels.h): the listener's JSON lines, key by key
// (tools/listen/README.md "JSON lines"). Internal to tlvlink_foxglove.
#ifndef TLVLINK_FOXGLOVE_PRIVATE
#error "channel_schemas.h is internal to tlvlink_foxglove"
#endif

#include <string>

namespace tlvlink::foxglove::internal {

struct ChannelSchemas {
  std::string hello, frame_prediction, grasp_prediction, stats, error, ack, nack, pong, frame_image;
};
// Built once, on first use.
const ChannelSchemas& channel_schemas();

}  // namespace tlvlink::foxglove::internal
