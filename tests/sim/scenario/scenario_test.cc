// Live scenarios: the recordings hold what the camera streams, at its pace, with B's phase; the
// truth matches the frames; `score` counts a perfect run as perfect and each planted mistake once.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tlvlink/capture/recording.h"
#include "tlvlink/capture/replay_source.h"
#include "tlvlink/score/score.h"
#include "tlvlink/sim/scenario.h"

namespace tlvlink::sim {
namespace {

using nlohmann::json;

class Scenario : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = (std::filesystem::temp_directory_path() /
            ("tlvlink_scenario_" + std::to_string(::getpid())))
               .string();
    ScenarioOptions o;
    o.sensor = "digit";  // YUYV 320x240 at 60 fps: small frames
    o.grasps = 2;
    o.presses = 1;
    o.seed = 5;
    auto r = write_scenario(o, dir_);
    ASSERT_TRUE(r.ok()) << r.error().message();
    report_ = *r;
  }
  static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }

  static std::vector<json> truth() {
    std::vector<json> out;
    std::ifstream in(dir_ + "/truth.jsonl");
    std::string line;
    while (std::getline(in, line)) out.push_back(json::parse(line));
    return out;
  }

  static std::string dir_;
  static ScenarioReport report_;
};
std::string Scenario::dir_;
ScenarioReport Scenario::report_;

TEST_F(Scenario, RecordingsHoldTheCamerasStreamAndTheTruthMatchesThem) {
  EXPECT_GT(report_.frames, 0);
  EXPECT_LT(report_.rendered, 2 * report_.frames);  // static stretches are repeats
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/.A.tlvraw.partial"));
  for (const char* finger : {"A", "B"}) {
    auto r = capture::RecordingReader::open(dir_ + "/" + finger + ".tlvraw");
    ASSERT_TRUE(r.ok()) << r.error().message();
    const capture::RecordingSummary& s = r->summary();
    EXPECT_EQ(s.format.format.format, image::PixelFormat::kYuyv);
    EXPECT_EQ(s.format.format.width, 320);
    EXPECT_EQ(s.format.format.height, 240);
    EXPECT_EQ(s.format.nominal_fps(), 60.0);
    EXPECT_EQ(static_cast<int64_t>(s.frames), report_.frames);
    EXPECT_EQ(s.first_offset_ns, std::string(finger) == "B" ? 7'000'000 : 0);
  }
  int64_t frames = 0, contact = 0, events = 0, grasps = 0;
  for (const json& j : truth()) {
    if (j["type"] == "frame") {
      ++frames;
      contact += j["contact"].get<bool>() ? 1 : 0;
      if (j["contact"].get<bool>()) {
        EXPECT_GE(j["event"].get<int>(), 0) << j.dump();
      }
    } else if (j["type"] == "event") {
      ++events;
      grasps += j["kind"] == "grasp" ? 1 : 0;
    }
  }
  EXPECT_EQ(frames, 2 * report_.frames);
  EXPECT_EQ(events, 3);
  EXPECT_EQ(grasps, 2);
  EXPECT_GT(contact, 0);
}

TEST_F(Scenario, ReplayDeliversEveryRecordedFrame) {
  capture::ReplayConfig c;
  c.path = dir_ + "/A.tlvraw";
  c.realtime = false;
  auto src = capture::make_replay_source(c);
  ASSERT_TRUE(src.ok() && (*src)->start().ok());
  int64_t n = 0;
  while ((*src)->next(10).ok()) ++n;
  EXPECT_EQ(n, report_.frames);
  EXPECT_EQ((*src)->stats().flagged_error, 0u);
}

// A daemon output written from the truth itself: every contact seen, every label right, one
// grasp record per scripted grasp with the right answer. Then one planted mistake of each kind.
TEST_F(Scenario, ScoreCountsAPerfectRunAsPerfectAndEachMistakeOnce) {
  const std::vector<json> t = truth();
  std::map<int, json> events;
  for (const json& j : t)
    if (j["type"] == "event") events[j["id"].get<int>()] = j;
  const auto write = [&](const std::string& path, bool plant) {
    std::ofstream out(path);
    bool missed = false, wrong = false;
    for (const json& j : t) {
      if (j["type"] != "frame") continue;
      json f = {{"type", "frame"}, {"sensor", j["finger"] == "A" ? "left" : "right"},
                {"seq", j["seq"]}, {"contact", j["contact"].get<bool>() ? "contact" : "none"},
                {"encoded", j["contact"]}};
      const int e = j["event"].get<int>();
      if (j["contact"].get<bool>() && e >= 0) {
        json heads;
        heads["hard_soft"] = {{"label", events[e]["hard_soft"]}};
        if (plant && !wrong) {
          heads["hard_soft"]["label"] = events[e]["hard_soft"] == "hard" ? "soft" : "hard";
          wrong = true;
        }
        f["heads"] = heads;
        if (plant && !missed && j["finger"] == "B") {
          f["contact"] = "none";
          f.erase("heads");
          missed = true;
        }
      }
      out << f.dump() << "\n";
    }
    for (const auto& [id, e] : events) {
      if (e["kind"] != "grasp") continue;
      const int64_t during = e["first_seq"].get<int64_t>() + 20;
      out << json{{"type", "grasp"}, {"computed", true},
                  {"prediction", e["success"].get<bool>() ? "success" : "failure"},
                  {"frames", json::array({{{"finger", "A"}, {"moment", "during"}, {"seq", during}}})}}
                 .dump()
          << "\n";
    }
  };
  const std::string perfect = dir_ + "/perfect.jsonl", planted = dir_ + "/planted.jsonl";
  write(perfect, false);
  write(planted, true);
  auto p = score::score_live_run(dir_ + "/truth.jsonl", perfect, {"left", "right"});
  ASSERT_TRUE(p.ok()) << p.error().message();
  EXPECT_EQ(p->frames, 2 * report_.frames);
  EXPECT_EQ(p->missed_contact, 0);
  EXPECT_EQ(p->false_contact, 0);
  EXPECT_EQ(p->contact_events.hits, 3);
  ASSERT_EQ(p->heads.size(), 1u);
  EXPECT_EQ(p->heads[0].frames.hits, p->heads[0].frames.total);
  EXPECT_EQ(p->truth_grasps, 2);
  EXPECT_EQ(p->grasp_accuracy.hits, 2);
  EXPECT_EQ(p->grasp_accuracy.total, 2);
  auto m = score::score_live_run(dir_ + "/truth.jsonl", planted, {"left", "right"});
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m->missed_contact, 1);
  EXPECT_EQ(m->missed_by_kind.at("grasp").hits, 1);  // B touches only in grasps
  EXPECT_EQ(p->missed_by_kind.at("press").hits, 0);
  EXPECT_EQ(m->heads[0].frames.hits, m->heads[0].frames.total - 1);  // the wrong label
  EXPECT_EQ(m->heads[0].frames.total, p->heads[0].frames.total - 1);  // the missed frame
  // Wrong inputs are errors naming the file.
  auto bad = score::score_live_run(dir_ + "/A.tlvraw", perfect, {"left", "right"});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(std::string(bad.error().message()).find("A.tlvraw"), std::string::npos);
}

}  // namespace
}  // namespace tlvlink::sim
