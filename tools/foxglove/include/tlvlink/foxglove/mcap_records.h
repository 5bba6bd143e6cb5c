#pragma once
// The MCAP records tlvlink writes and reads (https://mcap.dev/spec): what a schema, a channel
// and a message are, shared by mcap_writer.h and mcap_reader.h.

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace tlvlink::foxglove {

// The 8 bytes that open and close every MCAP file: 0x89 "MCAP0\r\n".
inline constexpr unsigned char kMcapMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

struct McapSchema {
  uint16_t id = 0;       // 1..65535 (0 means "no schema" in a channel)
  std::string name;      // e.g. "tlvlink.FramePrediction"
  std::string encoding;  // e.g. "jsonschema"
  std::string data;      // the schema itself
};

struct McapChannel {
  uint16_t id = 0;
  uint16_t schema_id = 0;        // 0: no schema (a channel of opaque bytes)
  std::string topic;             // e.g. "/tlvlink/frame_prediction"
  std::string message_encoding;  // e.g. "json"
  std::vector<std::pair<std::string, std::string>> metadata;
};

struct McapMessage {
  uint16_t channel_id = 0;
  uint32_t sequence = 0;      // per channel, from 0
  uint64_t log_time = 0;      // ns
  uint64_t publish_time = 0;  // ns
  std::vector<std::byte> data;
};

}  // namespace tlvlink::foxglove
