// `tlvlink score` reads a run from either side of the stream, in the one JSON-lines form
// (runtime/stream json_lines.h: tlvlinkd's jsonl: output and `tlvlink listen --json`, written here
// with that writer itself), and tlvlinkd's lines of before protocol 1.3: the same run gives the
// same report in every form. A 1.2 board's stream has no gate state: its contact flag is read.

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/temp_dir.h"
#include "tlvlink/protocol/wire.h"
#include "tlvlink/score/score.h"
#include "tlvlink/stream/json_lines.h"

namespace tlvlink {
namespace {

using nlohmann::json;

// One finger's frames: the gate's state, the label it gave (empty: the encoder did not run).
struct Frame {
  protocol::GateState gate;
  const char* label;
};
// Both fingers alike: two frames while the gate calibrates, an open gel, a grasp of a hard
// object (one label wrong), the gel open again.
constexpr Frame kRun[] = {{protocol::GateState::kCalibrating, "soft"},
                          {protocol::GateState::kCalibrating, "soft"},
                          {protocol::GateState::kNone, ""},
                          {protocol::GateState::kContact, "hard"},
                          {protocol::GateState::kContact, "soft"},
                          {protocol::GateState::kNone, ""}};
constexpr int kFrames = 6;

class ScoreForms : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream t(dir_ + "/truth.jsonl");
    t << json{{"type", "scenario"}, {"frames", kFrames}}.dump() << "\n"
      << json{{"type", "event"},
              {"id", 0},
              {"kind", "grasp"},
              {"success", true},
              {"hard_soft", "hard"}}
             .dump()
      << "\n";
    for (const char* finger : {"A", "B"}) {
      for (int k = 0; k < kFrames; ++k) {
        const bool contact = k == 3 || k == 4;
        t << json{{"type", "frame"},
                  {"finger", finger},
                  {"seq", k},
                  {"contact", contact},
                  {"force_n", contact ? 2.0 : 0.0},
                  {"event", k >= 2 && k <= 5 ? 0 : -1}}
                 .dump()
          << "\n";
      }
    }
  }

  score::ScoreReport score(const std::string& predictions) {
    auto r = score::score_live_run(dir_ + "/truth.jsonl", predictions, {"left", "right"});
    EXPECT_TRUE(r.ok()) << r.error().message();
    return r.ok() ? *r : score::ScoreReport{};
  }

  // The run in the one form. `names`: frames carry sensor_name and head names (a board's
  // lines, the listener's with a Hello); without, they are resolved from the hello line.
  // `gate`: a 1.3 board; without, a 1.2 board's (no gate state). `host`: the listener's keys.
  std::string one_form(const char* name, bool names, bool gate, bool host) {
    static constexpr std::string_view kLabels[] = {"soft", "hard"};
    const protocol::SensorInfo sensors[] = {{0, "left", "digit", "", "yuyv", 320, 240, 60.0f},
                                            {1, "right", "digit", "", "yuyv", 320, 240, 60.0f}};
    const protocol::HeadInfo heads[] = {{"hard_soft", protocol::HeadKind::kLinear, kLabels}};
    protocol::Hello hello;
    hello.sensors = sensors;
    hello.heads = heads;
    const std::string path = dir_ + "/" + name;
    std::ofstream out(path);
    stream::FixedLineBuffer<4096> l;
    uint32_t sequence = 0;
    const auto write = [&] {
      if (host) l.printf(",\"receive_ns\":%u", sequence);
      stream::json_end(l);
      out << l.view();
      l.clear();
    };
    stream::json_begin(l, protocol::MessageType::kHello, {sequence++, 0, 1});
    stream::json_fields(l, hello, protocol::schema_hash());
    write();
    for (uint8_t sensor = 0; sensor < 2; ++sensor) {
      for (int k = 0; k < kFrames; ++k) {
        static const float kSoft[] = {0.75f, 0.25f}, kHard[] = {0.25f, 0.75f};
        const std::string label = kRun[k].label;
        const protocol::HeadOutput head{0, label == "hard" ? kHard : kSoft};
        protocol::FramePrediction f;
        f.sensor = sensor;
        f.frame_sequence = static_cast<uint32_t>(k);
        f.timing = {1000, 1100, label.empty() ? 0 : 1200};  // infer_end_ns 0: not encoded
        f.contact = kRun[k].gate == protocol::GateState::kContact;
        if (!label.empty()) f.heads = std::span(&head, 1);
        if (gate) {
          f.gate = kRun[k].gate;
          f.gate_score_dn = f.contact ? 9.0f : 1.0f;
        }
        stream::json_begin(l, protocol::MessageType::kFramePrediction, {sequence++, 0, 2000});
        stream::json_fields(l, f, names ? &hello : nullptr);
        write();
      }
    }
    const protocol::GraspFrame frames[] = {{0, protocol::GraspPhase::kBefore, 2, 10},
                                           {0, protocol::GraspPhase::kDuring, 4, 20},
                                           {1, protocol::GraspPhase::kDuring, 4, 20}};
    protocol::GraspPrediction g;
    g.grasp_id = 1;
    g.status = protocol::GraspStatus::kComputed;
    g.probability = 0.875f;
    g.frames = frames;
    stream::json_begin(l, protocol::MessageType::kGraspPrediction, {sequence++, 0, 3000});
    stream::json_fields(l, g);
    write();
    return path;
  }

  // The same run as tlvlinkd wrote it before protocol 1.3.
  std::string old_form() {
    static constexpr const char* kGate[] = {"unknown", "calibrating", "none", "contact"};
    const std::string path = dir_ + "/old.jsonl";
    std::ofstream out(path);
    for (const char* sensor : {"left", "right"}) {
      for (int k = 0; k < kFrames; ++k) {
        json f = {{"type", "frame"},
                  {"sensor", sensor},
                  {"seq", k},
                  {"contact", kGate[static_cast<int>(kRun[k].gate)]},
                  {"encoded", *kRun[k].label != '\0'}};
        if (*kRun[k].label != '\0') f["heads"]["hard_soft"] = {{"label", kRun[k].label}};
        out << f.dump() << "\n";
      }
    }
    out << json{{"type", "grasp"},
                {"id", 1},
                {"computed", true},
                {"p_success", 0.875},
                {"prediction", "success"},
                {"frames", {{{"finger", "A"}, {"moment", "during"}, {"seq", 4}}}}}
               .dump()
        << "\n";
    return path;
  }

  ::tlvlink::testing::TempDir tmp_{"score_forms"};  // a fresh directory, removed with the fixture
  std::string dir_ = tmp_.path();
};

TEST_F(ScoreForms, EveryFormOfOneRunScoresTheSame) {
  const score::ScoreReport old = score(old_form());
  EXPECT_EQ(old.calibrating, 4);
  EXPECT_EQ(old.frames, 8);
  EXPECT_EQ(old.encoded, 4);
  ASSERT_EQ(old.heads.size(), 1u);
  EXPECT_EQ(old.heads[0].frames.hits, 2);
  EXPECT_EQ(old.heads[0].frames.total, 4);
  EXPECT_EQ(old.grasp_accuracy.hits, 1);
  const std::string want = score::format_score_json(old);
  // tlvlinkd's jsonl: lines; the listener's --json lines (host keys; names from the Hello
  // line when its frames carry none).
  EXPECT_EQ(score::format_score_json(score(one_form("board.jsonl", true, true, false))), want);
  EXPECT_EQ(score::format_score_json(score(one_form("listen.jsonl", true, true, true))), want);
  EXPECT_EQ(score::format_score_json(score(one_form("indexes.jsonl", false, true, true))), want);
}

TEST_F(ScoreForms, A12BoardsStreamIsScoredByItsContactFlag) {
  // No gate state: the calibrating frames are scored (as no contact), nothing else changes.
  const score::ScoreReport r = score(one_form("v12.jsonl", true, false, true));
  EXPECT_EQ(r.calibrating, 0);
  EXPECT_EQ(r.frames, 12);
  EXPECT_EQ(r.missed_contact, 0);
  EXPECT_EQ(r.false_contact, 0);
  EXPECT_EQ(r.grasp_accuracy.hits, 1);
}

}  // namespace
}  // namespace tlvlink
