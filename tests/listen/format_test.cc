// The JSON and text lines of every message type of the fixture recording: keys, names from the
// Hello, NaN as null, unknown enum values as numbers, host-clock times once the clock is known.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "fixture_recording.h"
#include "support/temp_dir.h"
#include "tlvlink/listen/client.h"
#include "tlvlink/listen/format.h"
#include "tlvlink/protocol/encode.h"

namespace tlvlink::listen {
namespace {

struct Printed {
  std::vector<nlohmann::json> json;
  std::vector<std::string> text;
};

Printed print_fixture() {
  testing::TempDir dir("fmt");
  EXPECT_TRUE(write_fixture_recording(dir / "f", false).ok());
  auto c = Client::open("replay:" + dir / "f").value();
  Printed p;
  std::optional<Message> hello;
  while (!c->ended()) {
    auto m = c->next(100);
    if (!m.ok() || !m.value()) continue;
    if (m.value()->type() == protocol::MessageType::kHello) hello = *m.value();
    const FormatContext context{hello ? &*hello : nullptr};
    p.json.push_back(nlohmann::json::parse(json_line(*m.value(), context)));
    p.text.push_back(text_line(*m.value(), context));
  }
  return p;
}

TEST(Format, JsonOfEveryMessageType) {
  const Printed p = print_fixture();
  ASSERT_EQ(p.json.size(), 13u);
  const auto& hello = p.json[0];
  EXPECT_EQ(hello["type"], "hello");
  EXPECT_EQ(hello["boot_id"], "0000000000005eed");
  EXPECT_EQ(hello["heads"][0]["labels"][1], "metal");
  EXPECT_NEAR(hello["heads"][0]["accuracy"].get<double>(), 0.158, 1e-6);
  // The fixture's heads record no cross-validation (minor 1's fields): null, and 0 groups.
  EXPECT_TRUE(hello["heads"][0]["accuracy_ci95"][0].is_null());
  EXPECT_TRUE(hello["heads"][0]["baseline_accuracy"].is_null());
  EXPECT_EQ(hello["heads"][0]["groups"], 0);
  EXPECT_EQ(hello["sensors"][1]["name"], "right");
  const auto& frame = p.json[1];
  EXPECT_EQ(frame["type"], "frame_prediction");
  EXPECT_EQ(frame["sensor_name"], "left");
  EXPECT_EQ(frame["heads"][0]["name"], "material");
  EXPECT_TRUE(frame["heads"][0].contains("top_label"));
  EXPECT_EQ(frame["embedding"].size(), 32u);
  EXPECT_EQ(frame["capture_host_ns"].get<int64_t>(),
            frame["capture_ns"].get<int64_t>() - 5'000'000'000)
      << "board times on the host clock once the offset is known";
  EXPECT_FALSE(p.json[2].contains("embedding"));
  EXPECT_EQ(p.json[3]["status"], "computed");
  EXPECT_EQ(p.json[3]["probability"], 0.8125);
  EXPECT_EQ(p.json[4]["status"], "not_computed");
  EXPECT_TRUE(p.json[4]["probability"].is_null()) << "never a made-up value";
  EXPECT_EQ(p.json[4]["reason"], "missing_finger");
  const auto& stats = p.json[5];
  EXPECT_EQ(stats["drops"][2]["cause"], 42) << "a cause this build does not know stays a number";
  EXPECT_EQ(stats["cpu_percent"], 37.5);
  EXPECT_EQ(p.json[6]["name"], "capture");
  EXPECT_EQ(p.json[7]["type"], "pong");
  // (t4 - t1) - (t3 - t2): received 200 us after the ping, 10 us spent on the board.
  EXPECT_EQ(p.json[7]["round_trip_ns"], 200'000 - 10'000) << p.json[7];
  EXPECT_EQ(p.json[8]["kind"], "set_config");
  EXPECT_EQ(p.json[10]["delayed"], true);
  EXPECT_FALSE(p.json[12].contains("send_host_ns"))
      << "after the board restarted, until a new Pong";
}

TEST(Format, TextLines) {
  const Printed p = print_fixture();
  EXPECT_EQ(
      p.text[0].rfind(
          "hello  test-board (host-x86_64, firmware 0.1.0-test) model fixture, 2 sensors, 2 heads",
          0),
      0u)
      << p.text[0];
  EXPECT_NE(p.text[1].find("material="), std::string::npos) << p.text[1];
  EXPECT_NE(p.text[1].find("embedding[32]"), std::string::npos);
  EXPECT_NE(p.text[3].find("grasp  #1 success p=0.812"), std::string::npos) << p.text[3];
  EXPECT_NE(p.text[4].find("not computed: missing_finger: sensor 1 sent no frame"),
            std::string::npos)
      << p.text[4];
  EXPECT_NE(p.text[5].find("42=7"), std::string::npos) << p.text[5];
  EXPECT_NE(p.text[8].find("nack   #3 set_config: unknown key 'treads'"), std::string::npos)
      << p.text[8];
  EXPECT_NE(p.text[10].find("[delayed]"), std::string::npos);
}

// Protocol 1.2's FrameImage: the JSON line carries the mask as rows of 0/1 and the JPEG as base64
// (every length's padding), the text line the sizes and the marked cells without the bytes.
TEST(Format, FrameImageLines) {
  static const uint8_t kMask[] = {0x81, 0x01};  // 3x3 cells: (0,0), (1,2), (2,2)
  for (const auto& [data, base64] :
       std::initializer_list<std::pair<std::vector<uint8_t>, std::string>>{
           {{0xFF}, "/w=="}, {{0xFF, 0xD8}, "/9g="}, {{0xFF, 0xD8, 0xFF}, "/9j/"}, {{}, ""}}) {
    protocol::FrameImage image;
    image.sensor = 1;
    image.frame_sequence = 12;
    image.kind = protocol::ImageKind::kInput;
    image.width = 224;
    image.height = 224;
    image.contact = true;
    image.mask_width = 3;
    image.mask_height = 3;
    image.mask = kMask;
    image.data = data;
    alignas(8) static std::byte scratch[protocol::kEncodeBufferSize];
    const auto payload = protocol::encode_payload(image, scratch).value();
    protocol::FrameHeader h;
    h.type = protocol::MessageType::kFrameImage;
    h.payload_length = static_cast<uint32_t>(payload.size());
    const Message m(h, payload, 1);
    const auto j = nlohmann::json::parse(json_line(m, {}));
    EXPECT_EQ(j["type"], "frame_image");
    EXPECT_EQ(j["kind"], "input");
    EXPECT_EQ(j["mask"], nlohmann::json({"100", "000", "011"}));
    EXPECT_EQ(j["data"], base64);
    EXPECT_EQ(text_line(m, {}), "image  s1 #12      input 224x224 jpeg " +
                                    std::to_string(data.size()) + " B contact, mask 3/9 cells");
  }
}

// Issue 31 item 4: a string that is not UTF-8 (nothing on the wire says it must be) is printed
// with U+FFFD for the bad bytes, and the messages after it still come (nlohmann::json threw).
TEST(Format, NonUtf8StringIsReplacedNotFatal) {
  testing::TempDir dir("fmt");
  ASSERT_TRUE(write_non_utf8_recording(dir / "r").ok());
  auto c = Client::open("replay:" + dir / "r").value();
  std::vector<std::string> lines;
  while (!c->ended()) {
    auto m = c->next(100);
    ASSERT_TRUE(m.ok());
    if (!m.value()) continue;
    lines.push_back(json_line(*m.value(), {}));
    EXPECT_FALSE(text_line(*m.value(), {}).empty());
  }
  ASSERT_EQ(lines.size(), 3u);
  const auto bad = nlohmann::json::parse(lines[1]);
  EXPECT_EQ(bad["text"], "bad \xEF\xBF\xBD\xEF\xBF\xBD bytes") << lines[1];
  EXPECT_EQ(nlohmann::json::parse(lines[2])["text"], "after");
}

}  // namespace
}  // namespace tlvlink::listen
