// The one JSON-lines form (runtime/stream json_lines.h): every message kind with the listener's
// keys, strings escaped and invalid UTF-8 replaced byte for byte as nlohmann::json does, floats as
// nlohmann and Python print them, a line longer than the buffer reported (never cut), and no
// heap allocation per line.
#include "tlvlink/stream/json_lines.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/alloc_counter.h"
#include "tlvlink/protocol/wire.h"

namespace tlvlink::stream {
namespace {

using nlohmann::json;

// The Hello the other messages are named by.
struct Names {
  static constexpr std::string_view kLabels[] = {"soft", "hard"};
  static constexpr std::string_view kStages[] = {"dequeue", "decode"};
  protocol::SensorInfo sensors[2] = {{0, "left", "digit", "D1", "yuyv", 320, 240, 60.0f},
                                     {1, "right", "digit", "D2", "yuyv", 320, 240, 60.0f}};
  protocol::HeadInfo heads[1] = {{"hard_soft", protocol::HeadKind::kLinear, kLabels, 0.75f}};
  protocol::Hello hello;
  Names() {
    hello.device = "board";
    hello.board = "host";
    hello.firmware_version = "1.0";
    hello.boot_id = 0x5EED;
    hello.model_id = "model";
    hello.model_checksum = 42;
    hello.sensors = sensors;
    hello.heads = heads;
    hello.stage_names = kStages;
    hello.embedding_dim = 2;
  }
};

template <typename M, typename... Args>
json line_of(protocol::MessageType type, const M& m, Args... args) {
  FixedLineBuffer<4096> out;
  json_begin(out, type, {7, protocol::kFlagDelayed, 1000});
  json_fields(out, m, args...);
  json_end(out);
  EXPECT_FALSE(out.overflowed());
  EXPECT_EQ(out.view().back(), '\n');
  EXPECT_EQ(out.view().find('\n'), out.view().size() - 1) << "one line";
  return json::parse(out.view());
}

TEST(JsonLines, HeaderKeys) {
  const Names n;
  const json j = line_of(protocol::MessageType::kHello, n.hello, protocol::schema_hash());
  EXPECT_EQ(j["type"], "hello");
  EXPECT_EQ(j["sequence"], 7);
  EXPECT_EQ(j["flags"], 1);
  EXPECT_EQ(j["delayed"], true);
  EXPECT_EQ(j["send_ns"], 1000);
}

TEST(JsonLines, Hello) {
  const Names n;
  const json j = line_of(protocol::MessageType::kHello, n.hello, uint64_t{0x094a2aca5021ce1d});
  EXPECT_EQ(j["boot_id"], "0000000000005eed");
  EXPECT_EQ(j["schema_hash"], "094a2aca5021ce1d");
  EXPECT_EQ(j["schema_matches"], false) << "another build's schema";
  EXPECT_EQ(j["model_checksum"], "000000000000002a");
  EXPECT_EQ(j["sensors"][1], json({{"index", 1},
                                   {"name", "right"},
                                   {"model", "digit"},
                                   {"serial", "D2"},
                                   {"pixel_format", "yuyv"},
                                   {"width", 320},
                                   {"height", 240},
                                   {"fps", 60.0}}));
  EXPECT_EQ(j["heads"][0]["kind"], "linear");
  EXPECT_EQ(j["heads"][0]["labels"], json({"soft", "hard"}));
  EXPECT_EQ(j["heads"][0]["accuracy"], 0.75);
  EXPECT_TRUE(j["heads"][0]["majority_rate"].is_null()) << "NaN: not recorded";
  EXPECT_EQ(j["heads"][0]["accuracy_ci95"], json({nullptr, nullptr}));
  EXPECT_EQ(j["stage_names"], json({"dequeue", "decode"}));
  EXPECT_EQ(j["embedding_dim"], 2);
  EXPECT_EQ(j["clock"], "CLOCK_MONOTONIC");
  EXPECT_EQ(j["max_frame_size"], protocol::kMaxFrameSize);
}

TEST(JsonLines, FramePredictionNamedByTheHello) {
  const Names n;
  static const float kProbs[] = {0.25f, 0.75f};
  static const uint32_t kStages[] = {100, 200};
  static const float kEmbedding[] = {0.5f, -1.0f};
  const protocol::HeadOutput heads[] = {{0, kProbs}, {5, kProbs}};  // head 5: not in the Hello
  protocol::FramePrediction f;
  f.sensor = 1;
  f.frame_sequence = 41;
  f.timing = {2000, 2100, 2900};
  f.stage_ns = kStages;
  f.contact = true;
  f.heads = heads;
  f.embedding = kEmbedding;
  f.gate = protocol::GateState::kContact;
  f.gate_score_dn = 12.5f;
  const json j = line_of(protocol::MessageType::kFramePrediction, f, &n.hello);
  EXPECT_EQ(j["type"], "frame_prediction");
  EXPECT_EQ(j["sensor"], 1);
  EXPECT_EQ(j["sensor_name"], "right");
  EXPECT_EQ(j["frame_sequence"], 41);
  EXPECT_EQ(j["capture_ns"], 2000);
  EXPECT_EQ(j["infer_start_ns"], 2100);
  EXPECT_EQ(j["infer_end_ns"], 2900);
  EXPECT_EQ(j["stage_ns"], json({100, 200}));
  EXPECT_EQ(j["contact"], true);
  EXPECT_EQ(j["gate"], "contact");
  EXPECT_EQ(j["gate_score_dn"], 12.5);
  EXPECT_EQ(j["heads"][0], json({{"head", 0},
                                 {"name", "hard_soft"},
                                 {"probabilities", {0.25, 0.75}},
                                 {"top_label", "hard"},
                                 {"top_probability", 0.75}}));
  EXPECT_FALSE(j["heads"][1].contains("name")) << "a head the Hello does not list: by index";
  EXPECT_EQ(j["embedding"], json({0.5, -1.0}));
  // Without a Hello: indexes only; a 1.2 board's frame: gate unknown, score null.
  protocol::FramePrediction old;
  old.heads = heads;
  const json o = line_of(protocol::MessageType::kFramePrediction, old, nullptr);
  EXPECT_FALSE(o.contains("sensor_name"));
  EXPECT_FALSE(o["heads"][0].contains("name"));
  EXPECT_FALSE(o["heads"][0].contains("top_label"));
  EXPECT_EQ(o["gate"], "unknown");
  EXPECT_TRUE(o["gate_score_dn"].is_null());
  EXPECT_EQ(o["heads"].size(), 2u);
  EXPECT_FALSE(o.contains("embedding")) << "not sent";
  protocol::FramePrediction gated;
  gated.gate = static_cast<protocol::GateState>(9);  // a newer board's state: its number
  EXPECT_EQ(line_of(protocol::MessageType::kFramePrediction, gated, nullptr)["gate"], 9);
}

TEST(JsonLines, GraspStatsErrorAndReplies) {
  const protocol::GraspFrame frames[] = {{1, protocol::GraspPhase::kDuring, 9, 100}};
  protocol::GraspPrediction g;
  g.grasp_id = 3;
  g.frames = frames;
  g.reason = protocol::GraspReason::kOther;
  g.reason_text = "missing finger B";
  g.closed_ns = 50;
  json j = line_of(protocol::MessageType::kGraspPrediction, g);
  EXPECT_EQ(j["status"], "not_computed");
  EXPECT_TRUE(j["probability"].is_null()) << "never a made-up value";
  EXPECT_EQ(j["reason"], "other");
  EXPECT_EQ(j["reason_text"], "missing finger B");
  EXPECT_EQ(j["frames"][0],
            json({{"sensor", 1}, {"phase", "during"}, {"frame_sequence", 9}, {"capture_ns", 100}}));
  EXPECT_EQ(j["phase_source"], "command");
  EXPECT_EQ(j["closed_ns"], 50);
  const protocol::SensorStats sensors[] = {{0, 25.0f, 100, 40, 60}};
  const protocol::DropCount drops[] = {{protocol::DropCause::kQueueFull, 2, protocol::kNoSensor},
                                       {static_cast<protocol::DropCause>(42), 7, 0}};
  protocol::Stats s;
  s.uptime_ns = 5;
  s.sensors = sensors;
  s.drops = drops;
  s.cpu_percent = 37.5f;
  s.link.link_up = true;
  s.link.queue_capacity_bytes = 4096;
  j = line_of(protocol::MessageType::kStats, s);
  EXPECT_EQ(j["sensors"][0],
            json({{"sensor", 0}, {"fps", 25.0}, {"frames", 100}, {"inferred", 40}, {"gated", 60}}));
  EXPECT_EQ(j["drops"][0]["cause"], "queue_full");
  EXPECT_EQ(j["drops"][1]["cause"], 42) << "a cause this build does not know stays a number";
  EXPECT_EQ(j["cpu_percent"], 37.5);
  EXPECT_EQ(j["link"]["link_up"], true);
  EXPECT_EQ(j["link"]["queue_capacity_bytes"], 4096);
  j = line_of(protocol::MessageType::kError, protocol::ErrorReport{3, "capture", "gone", 1});
  EXPECT_EQ(j,
            json::parse(R"({"type":"error","sequence":7,"flags":1,"delayed":true,)"
                        R"("send_ns":1000,"code":3,"name":"capture","text":"gone","sensor":1})"));
  j = line_of(protocol::MessageType::kNack,
              protocol::Nack{3, protocol::CommandKind::kSetConfig, 513, "no"});
  EXPECT_EQ(j["kind"], "set_config");
  EXPECT_EQ(j["text"], "no");
  j = line_of(protocol::MessageType::kPong, protocol::Pong{9, 100, 200});
  EXPECT_EQ(j["host_send_ns"], 100);
  EXPECT_EQ(j["board_receive_ns"], 200);
}

// The listener's lines were nlohmann::json's: the same bytes for the same strings and numbers.
TEST(JsonLines, StringsAndNumbersAsNlohmannWritesThem) {
  for (const std::string& s :
       {std::string("plain"), std::string("quote \" backslash \\ slash /"),
        std::string("\b\f\n\r\t and \x01\x1f\x7f"),
        std::string("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80"), std::string("bad \xff\xfe bytes"),
        std::string("cut \xE2\x82"), std::string("cut \xE2\x82x"),
        std::string("overlong \xC0\xAF, surrogate \xED\xA0\x80, too big \xF4\x90\x80\x80"),
        std::string("nul \0 inside", 13)}) {
    FixedLineBuffer<512> out;
    out.json_string(s);
    EXPECT_EQ(out.view(), json(s).dump(-1, ' ', false, json::error_handler_t::replace)) << s;
  }
  for (const float v :
       {0.0f, 1.0f, 60.0f, -2.5f, 0.1f, 0.24239909648895264f, 4.640927e-05f, 1e-7f, 123456.789f,
        3.0e20f, std::numeric_limits<float>::max(), std::numeric_limits<float>::denorm_min()}) {
    FixedLineBuffer<64> out;
    out.json_number(v);
    EXPECT_EQ(out.view(), json(v).dump()) << v;
    EXPECT_EQ(static_cast<float>(json::parse(out.view()).get<double>()), v) << "reads back";
  }
  for (const float v :
       {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    FixedLineBuffer<64> out;
    out.json_number(v);
    EXPECT_EQ(out.view(), "null");
  }
}

// Random floats of every magnitude (bit patterns; seed printed): the same number as
// nlohmann::json writes, never longer. The text differs in the last digit for ~1 % of them:
// nlohmann's Grisu2 may end an exact tie (...3125 -> ...313) or keep a digit more where
// std::to_chars gives the shortest, closest digits (what Python's repr gives).
TEST(JsonLines, RandomFloatsAsNlohmannWritesThem) {
  constexpr uint64_t kSeed = 20261205;
  std::mt19937_64 random(kSeed);
  int checked = 0, text_differs = 0;
  for (int i = 0; i < 100000; ++i) {
    const auto bits = static_cast<uint32_t>(random());
    float v;
    std::memcpy(&v, &bits, sizeof v);
    if (!std::isfinite(v)) continue;
    FixedLineBuffer<64> out;
    out.json_number(v);
    const std::string want = json(v).dump();
    ++checked;
    text_differs += out.view() == want ? 0 : 1;
    ASSERT_EQ(json::parse(out.view()).get<double>(), json::parse(want).get<double>())
        << "seed " << kSeed << " value " << i << ": " << out.view() << " vs " << want;
    ASSERT_LE(out.view().size(), want.size()) << out.view() << " vs " << want;
  }
  EXPECT_LT(text_differs, checked / 20) << text_differs << " of " << checked;
}

// As the daemon did: a line that does not fit is reported, and what was written is not a line.
TEST(JsonLines, ALineLongerThanTheBufferIsReportedNotCut) {
  static const float kProbs[64] = {};
  const protocol::HeadOutput heads[] = {{0, kProbs}, {1, kProbs}, {2, kProbs}};
  protocol::FramePrediction f;
  f.heads = heads;
  FixedLineBuffer<256> out;
  json_begin(out, protocol::MessageType::kFramePrediction, {});
  json_fields(out, f, nullptr);
  json_end(out);
  EXPECT_TRUE(out.overflowed());
  EXPECT_LT(out.view().size(), out.capacity());
  out.clear();
  EXPECT_FALSE(out.overflowed()) << "the next line starts clean";
  json_begin(out, protocol::MessageType::kAck, {});
  json_fields(out, protocol::Ack{1, protocol::CommandKind::kStart});
  json_end(out);
  EXPECT_FALSE(out.overflowed());
  EXPECT_EQ(json::parse(out.view())["kind"], "start");
}

// STYLE.md: setup allocates, the frame loop does not (the daemon formats a line per frame).
TEST(JsonLines, NoHeapAllocationPerLine) {
  const Names n;
  static const float kProbs[] = {0.25f, 0.75f};
  static const uint32_t kStages[] = {100, 200};
  const protocol::HeadOutput heads[] = {{0, kProbs}};
  protocol::FramePrediction f;
  f.stage_ns = kStages;
  f.heads = heads;
  f.gate_score_dn = 3.25f;
  FixedLineBuffer<4096> out;
  testing::start_counting_allocations();
  for (int i = 0; i < 100; ++i) {
    out.clear();
    json_begin(out, protocol::MessageType::kFramePrediction, {static_cast<uint32_t>(i), 0, i});
    json_fields(out, f, &n.hello);
    json_end(out);
    out.clear();
    json_begin(out, protocol::MessageType::kError, {});
    json_fields(out, protocol::ErrorReport{0, "info", "bad \xff text", 255});
    json_end(out);
  }
  EXPECT_EQ(testing::stop_counting_allocations(), 0u);
  EXPECT_FALSE(out.overflowed());
}

}  // namespace
}  // namespace tlvlink::stream
