// The channel table (tools/foxglove/channels.h) on every message of the fixture recording: each
// message's JSON is the listener's JSON line plus `timestamp` (its log time), and every key it
// carries is declared by its channel's JSON Schema.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>

#include "fixture_recording.h"
#include "support/temp_dir.h"
#include "tlvlink/foxglove/channels.h"
#include "tlvlink/listen/client.h"
#include "tlvlink/protocol/encode.h"

namespace tlvlink::foxglove {
namespace {

using nlohmann::json;

struct Mapped {
  std::string line;  // json_line
  listen::Message message;
  std::optional<ChannelMessage> channel;
};

std::vector<Mapped> map_fixture() {
  testing::TempDir dir("chan");
  EXPECT_TRUE(listen::write_fixture_recording(dir / "f", false).ok());
  auto c = listen::Client::open("replay:" + dir / "f").value();
  std::vector<Mapped> out;
  std::optional<listen::Message> hello;
  while (!c->ended()) {
    auto m = c->next(100);
    if (!m.ok() || !m.value()) continue;
    if (m.value()->type() == protocol::MessageType::kHello) hello = *m.value();
    const listen::FormatContext context{hello ? &*hello : nullptr};
    out.push_back({listen::json_line(*m.value(), context), *m.value(),
                   to_channel_message(*m.value(), context)});
  }
  return out;
}

// Every key of `value` (recursively, through arrays) is in `schema`'s properties.
void expect_declared(const json& value, const json& schema, const std::string& where) {
  if (value.is_object()) {
    ASSERT_TRUE(schema.contains("properties"))
        << where << ": an object where the schema has no properties";
    for (const auto& [k, v] : value.items()) {
      ASSERT_TRUE(schema["properties"].contains(k)) << where << "." << k << " is not in the schema";
      expect_declared(v, schema["properties"][k], where + "." + k);
    }
  } else if (value.is_array() && schema.contains("items")) {
    for (const json& v : value) expect_declared(v, schema["items"], where + "[]");
  }
}

TEST(Channels, TheTableHasUniqueIdsTopicsAndJsonSchemas) {
  std::set<uint16_t> ids;
  std::set<std::string_view> topics;
  for (const ChannelSpec& c : channel_table()) {
    EXPECT_TRUE(ids.insert(c.id).second) << c.id;
    EXPECT_TRUE(topics.insert(c.topic).second) << c.topic;
    const json schema = json::parse(c.schema);
    EXPECT_EQ(schema["type"], "object") << c.topic;
    EXPECT_TRUE(schema["properties"].contains("timestamp")) << c.topic;
  }
  EXPECT_EQ(ids.size(), 9u);
}

// The frame image channel (issue 33 item 1): foxglove.CompressedImage's keys (frame_id, format,
// data in base64) on the listener's line, so Foxglove's Image panel shows the gel.
TEST(Channels, AFrameImageIsACompressedImage) {
  static const uint8_t kJpeg[] = {0xFF, 0xD8, 0x01, 0x02, 0xFF, 0xD9};
  static const uint8_t kMask[] = {0x01, 0x00, 0x00};
  protocol::FrameImage image;
  image.sensor = 1;
  image.frame_sequence = 7;
  image.capture_ns = 5'000'000'000;
  image.width = 64;
  image.height = 48;
  image.contact = true;
  image.mask_width = 6;
  image.mask_height = 4;
  image.mask = kMask;
  image.data = kJpeg;
  alignas(8) static std::byte scratch[protocol::kEncodeBufferSize];
  const auto payload = protocol::encode_payload(image, scratch).value();
  protocol::FrameHeader h;
  h.type = protocol::MessageType::kFrameImage;
  h.payload_length = static_cast<uint32_t>(payload.size());
  h.send_ns = 5'001'000'000;
  const listen::Message m(h, payload, 6'000'000'000);
  const std::optional<ChannelMessage> c = to_channel_message(m, listen::FormatContext{});
  ASSERT_TRUE(c.has_value());
  const ChannelSpec& spec = channel_table()[c->channel_id - 1];
  EXPECT_EQ(spec.topic, "/tlvlink/frame_image");
  EXPECT_EQ(spec.schema_name, "foxglove.CompressedImage");
  json j = json::parse(c->json);
  expect_declared(j, json::parse(spec.schema), std::string(spec.topic));
  EXPECT_EQ(j["frame_id"], "sensor1") << "no Hello: the sensor's number";
  EXPECT_EQ(j["format"], "jpeg");
  EXPECT_EQ(j["data"], "/9gBAv/Z");
  EXPECT_EQ(j["mask"], json({"100000", "000000", "000000", "000000"}));
  EXPECT_EQ(j["timestamp"]["sec"], 6) << "no clock estimate: the receive time";
  j.erase("timestamp");
  j.erase("frame_id");
  EXPECT_EQ(j.dump(), json::parse(listen::json_line(m, listen::FormatContext{})).dump());
}

TEST(Channels, EveryMessageIsItsJsonLinePlusItsLogTime) {
  const std::vector<Mapped> all = map_fixture();
  ASSERT_EQ(all.size(), 13u);  // the fixture's messages (tests/listen/format_test.cc)
  std::set<uint16_t> used;
  for (const Mapped& m : all) {
    ASSERT_TRUE(m.channel.has_value()) << m.line;
    const ChannelMessage& c = *m.channel;
    used.insert(c.channel_id);
    json j = json::parse(c.json);
    const json stamp = j["timestamp"];
    j.erase("timestamp");
    EXPECT_EQ(j.dump(), json::parse(m.line).dump()) << "the listener's line, key for key";
    EXPECT_EQ(c.json.substr(0, m.line.size() - 1), m.line.substr(0, m.line.size() - 1))
        << "and byte for byte";
    EXPECT_EQ(stamp["sec"].get<int64_t>() * 1'000'000'000 + stamp["nsec"].get<int64_t>(),
              c.log_time_ns);
    EXPECT_EQ(c.publish_time_ns, m.message.receive_ns());
    const ChannelSpec& spec = channel_table()[c.channel_id - 1];
    EXPECT_EQ(std::string(spec.topic), "/tlvlink/" + j["type"].get<std::string>())
        << "one channel per type";
    expect_declared(j, json::parse(spec.schema), std::string(spec.topic));
    // Log time: the board's time on the host clock once the offset is known (capture time for
    // frames).
    if (!m.message.clock().valid) {
      EXPECT_EQ(c.log_time_ns, m.message.receive_ns()) << m.line;
    } else if (j["type"] == "frame_prediction") {
      EXPECT_EQ(c.log_time_ns, j["capture_host_ns"].get<int64_t>());
    } else {
      EXPECT_EQ(c.log_time_ns, j["send_host_ns"].get<int64_t>());
    }
  }
  EXPECT_GE(used.size(), 7u) << "the fixture has every type but error or pong at least";
}

}  // namespace
}  // namespace tlvlink::foxglove
