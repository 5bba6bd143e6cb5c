// Live scenarios: the recordings hold what the camera streams, at its pace, with B's phase; the
// truth matches the frames; `score` counts a perfect run as perfect and each planted mistake once,
// scores head labels on frames in contact only, and gives event figures a 95 % interval.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/temp_dir.h"
#include "tlvlink/capture/recording.h"
#include "tlvlink/capture/replay_source.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/score/compare.h"
#include "tlvlink/score/score.h"
#include "tlvlink/sim/scenario.h"

namespace tlvlink::sim {
namespace {

using nlohmann::json;

class Scenario : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    tmp_ = std::make_unique<::tlvlink::testing::TempDir>("scenario");
    dir_ = *tmp_ / "run";  // write_scenario makes it
    ScenarioOptions o;
    o.sensor = "digit";  // YUYV 320x240 at 60 fps: small frames
    o.grasps = 2;
    o.presses = 1;
    o.seed = 5;
    o.offline = true;
    auto r = write_scenario(o, dir_);
    ASSERT_TRUE(r.ok()) << r.error().message();
    report_ = *r;
  }
  static void TearDownTestSuite() { tmp_.reset(); }

  static std::vector<json> truth() {
    std::vector<json> out;
    std::ifstream in(dir_ + "/truth.jsonl");
    std::string line;
    while (std::getline(in, line)) out.push_back(json::parse(line));
    return out;
  }

  static std::unique_ptr<::tlvlink::testing::TempDir> tmp_;  // the suite's directory
  static std::string dir_;
  static ScenarioReport report_;
};
std::unique_ptr<::tlvlink::testing::TempDir> Scenario::tmp_;
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
      } else {
        // An open gel differs from the open gel by camera noise only: below the level at which
        // `score` calls a contact invisible (kInvisibleSignalDn), which this justifies.
        EXPECT_LT(j["signal_dn"].get<double>(), score::kInvisibleSignalDn) << j.dump();
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

// DIGIT: the processed view is 240 wide, 320 high, upright. The offline recordings hold it
// exactly (RGB24); the dataset recordings hold the datasets' JPEG q90 of the same frames, within
// that codec's error of them (a textured frame: ~1-2 DN on average; 4 allows for the 4:2:0
// chroma at colour edges while a wrong frame or view would differ by tens of DN).
TEST_F(Scenario, OfflineRecordingsHoldTheSameFramesExactlyAndAsTheDatasetsStoreThem) {
  for (const char* finger : {"A", "B"}) {
    for (const char* kind : {"offline", "dataset"}) {
      auto r = capture::RecordingReader::open(dir_ + "/" + finger + "." + kind + ".tlvraw");
      ASSERT_TRUE(r.ok()) << r.error().message();
      const capture::RecordingSummary& s = r->summary();
      EXPECT_EQ(s.format.format.format, std::string(kind) == "offline"
                                            ? image::PixelFormat::kRgb24
                                            : image::PixelFormat::kMjpeg);
      EXPECT_EQ(s.format.format.width, 240);
      EXPECT_EQ(s.format.format.height, 320);
      EXPECT_EQ(static_cast<int64_t>(s.frames), report_.frames);
      EXPECT_EQ(s.first_offset_ns, std::string(finger) == "B" ? 7'000'000 : 0);
    }
  }
  const auto frame_at = [](const char* kind, int index) {
    capture::ReplayConfig c;
    c.path = dir_ + "/A." + kind + ".tlvraw";
    c.realtime = false;
    auto src = capture::make_replay_source(c);
    EXPECT_TRUE(src.ok() && (*src)->start().ok());
    std::vector<uint8_t> bytes;
    for (int i = 0; i <= index; ++i) {
      auto frame = (*src)->next(10);
      EXPECT_TRUE(frame.ok());
      if (!frame.ok()) break;
      bytes.assign(frame->bytes.begin(), frame->bytes.end());
    }
    return bytes;
  };
  const std::vector<uint8_t> exact = frame_at("offline", 10);
  ASSERT_EQ(exact.size(), size_t{240} * 320 * 3);
  auto decoded = image::decode_jpeg(frame_at("dataset", 10), "dataset frame");
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  ASSERT_EQ(decoded->width, 240);
  ASSERT_EQ(decoded->height, 320);
  ASSERT_EQ(decoded->pixels.size(), exact.size());
  double sum = 0;
  for (size_t i = 0; i < exact.size(); ++i)
    sum += std::abs(int{exact[i]} - int{decoded->pixels[i]});
  EXPECT_LE(sum / static_cast<double>(exact.size()), 4.0);
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
      json f = {{"type", "frame"},
                {"sensor", j["finger"] == "A" ? "left" : "right"},
                {"seq", j["seq"]},
                {"contact", j["contact"].get<bool>() ? "contact" : "none"},
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
      out << json{{"type", "grasp"},
                  {"computed", true},
                  {"prediction", e["success"].get<bool>() ? "success" : "failure"},
                  {"frames",
                   json::array({{{"finger", "A"}, {"moment", "during"}, {"seq", during}}})}}
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
  EXPECT_EQ(m->heads[0].frames.hits, m->heads[0].frames.total - 1);   // the wrong label
  EXPECT_EQ(m->heads[0].frames.total, p->heads[0].frames.total - 1);  // the missed frame
  // Live (perfect) against offline (planted) on the same frames: only frames both predicted are
  // paired (the planted miss drops one), the planted wrong label is the whole difference, and
  // grasps agree.
  auto c =
      score::compare_live_offline({{dir_ + "/truth.jsonl", perfect, planted}}, {"left", "right"});
  ASSERT_TRUE(c.ok()) << c.error().message();
  ASSERT_EQ(c->heads.size(), 1u);
  const score::PairedRate& f = c->heads[0].frames;
  EXPECT_EQ(f.live.total, p->heads[0].frames.total - 1);
  EXPECT_EQ(f.live.hits, f.live.total);
  EXPECT_EQ(f.offline.hits, f.live.total - 1);
  EXPECT_NEAR(f.difference(), 1.0 / static_cast<double>(f.live.total), 1e-12);
  EXPECT_LE(f.difference_low, f.difference());
  EXPECT_GE(f.difference_high, f.difference());
  EXPECT_EQ(c->grasps.live.hits, 2);
  EXPECT_EQ(c->grasps.offline.hits, 2);
  EXPECT_EQ(c->grasps_scripted, 2);
  EXPECT_EQ(c->live.missed_contact, 0);
  EXPECT_EQ(c->offline.missed_contact, 1);
  const std::string exact = score::format_live_offline(*c);
  EXPECT_NE(exact.find("live - offline"), std::string::npos);
  EXPECT_NE(exact.find("targets: "), std::string::npos);
  // Against the datasets' copy the columns say so and no target is judged.
  const std::string copy = score::format_live_offline(*c, score::Reference::kDatasetCopy);
  EXPECT_NE(copy.find("live - dataset"), std::string::npos);
  EXPECT_EQ(copy.find("offline"), std::string::npos) << copy;
  EXPECT_EQ(copy.find("targets: "), std::string::npos) << copy;
  EXPECT_EQ(copy.find("OVER TARGET"), std::string::npos) << copy;
  const std::string copy_json = score::format_live_offline_json(*c, score::Reference::kDatasetCopy);
  EXPECT_NE(copy_json.find("\"reference\":\"dataset\""), std::string::npos);
  EXPECT_EQ(copy_json.find("meets_target"), std::string::npos);
  auto pooled = score::compare_live_offline(
      {{dir_ + "/truth.jsonl", perfect, planted}, {dir_ + "/truth.jsonl", perfect, planted}},
      {"left", "right"});
  ASSERT_TRUE(pooled.ok());
  EXPECT_EQ(pooled->heads[0].frames.live.total, 2 * f.live.total);  // runs pool
  EXPECT_EQ(pooled->grasps_scripted, 4);
  EXPECT_EQ(score::compare_live_offline({{dir_ + "/truth.jsonl", perfect, ""}}, {"left", "right"})
                .error()
                .code(),
            ErrorCode::kInvalidArgument);
  // Wrong inputs are errors naming the file.
  auto bad = score::score_live_run(dir_ + "/A.tlvraw", perfect, {"left", "right"});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(std::string(bad.error().message()).find("A.tlvraw"), std::string::npos);
}

// A label the daemon gives a frame the renderer shows without contact (the gate's false contact at
// the end of a press) is the gate's mistake, not the head's: counted apart, and it is not the
// event's answer.
TEST(Score, LabelsOfFramesWithoutContactAreCountedApart) {
  const ::tlvlink::testing::TempDir tmp("score");  // removed at the end of the test
  const std::string dir = tmp.path();
  {
    std::ofstream t(dir + "/truth.jsonl");
    t << R"({"type":"scenario","sensor":"gelsight-mini","fps":25,"frames":4,"fingers":["A","B"]})"
         "\n"
      << R"({"type":"event","id":0,"kind":"press","success":null,"material":"metal","hard_soft":"hard","rough_smooth":null})"
         "\n";
    const bool contact[4] = {false, true, false, false};
    const int event[4] = {-1, 0, 0, -1};
    for (int k = 0; k < 4; ++k) {
      t << json{{"type", "frame"},
                {"finger", "A"},
                {"seq", k},
                {"contact", contact[k]},
                {"force_n", contact[k] ? 3.0 : 0.0},
                {"event", event[k]}}
               .dump()
        << "\n"
        << json{{"type", "frame"},  {"finger", "B"},  {"seq", k},
                {"contact", false}, {"force_n", 0.0}, {"event", -1}}
               .dump()
        << "\n";
    }
    std::ofstream p(dir + "/predictions.jsonl");
    const auto frame = [&](int seq, const char* gate, const char* material) {
      json f = {{"type", "frame"}, {"sensor", "left"}, {"seq", seq}, {"contact", gate}};
      if (material != nullptr) f["heads"]["material"] = {{"label", material}};
      p << f.dump() << "\n";
    };
    frame(0, "none", nullptr);
    frame(1, "contact", "metal");
    frame(2, "contact", "glass");  // the imprint has gone; the gate still says contact
    frame(3, "none", nullptr);
  }
  auto r =
      score::score_live_run(dir + "/truth.jsonl", dir + "/predictions.jsonl", {"left", "right"});
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_EQ(r->false_contact, 1);
  ASSERT_EQ(r->heads.size(), 1u);
  EXPECT_EQ(r->heads[0].frames.hits, 1);
  EXPECT_EQ(r->heads[0].frames.total, 1);
  EXPECT_EQ(r->heads[0].without_contact, 1);
  EXPECT_EQ(r->heads[0].events.hits, 1);  // the answer given in contact
  EXPECT_EQ(r->heads[0].events.total, 1);
  EXPECT_NE(score::format_score(*r).find("1 labelled frames without contact"), std::string::npos);
}

// A press head ("hard_soft_press", tools/eval press_head.h) is scored against the label it is
// named after; per event, its answer on the event's last frame (the one over the whole press).
TEST(Score, APressHeadIsScoredAgainstItsLabelAtThePressesEnd) {
  const ::tlvlink::testing::TempDir tmp("press");  // removed at the end of the test
  const std::string dir = tmp.path();
  {
    std::ofstream t(dir + "/truth.jsonl");
    t << R"({"type":"scenario","sensor":"digit","fps":60,"frames":6,"fingers":["A","B"]})"
         "\n"
      << R"({"type":"event","id":0,"kind":"press","success":null,"material":"rubber","hard_soft":"soft","rough_smooth":null})"
         "\n";
    for (int k = 0; k < 6; ++k) {
      for (const char* finger : {"A", "B"}) {
        const bool in = finger[0] == 'A' && k >= 1;
        t << json{{"type", "frame"}, {"finger", finger},          {"seq", k},
                  {"contact", in},   {"force_n", in ? 2.0 : 0.0}, {"event", in ? 0 : -1}}
                 .dump()
          << "\n";
      }
    }
    std::ofstream p(dir + "/predictions.jsonl");
    // The press head answers from the contact's fourth frame (seq 4) on: wrong, then right.
    const char* press[6] = {nullptr, nullptr, nullptr, nullptr, "hard", "soft"};
    for (int k = 0; k < 6; ++k) {
      json f = {{"type", "frame"},
                {"sensor", "left"},
                {"seq", k},
                {"contact", k >= 1 ? "contact" : "none"}};
      if (k >= 1) f["heads"]["hard_soft"] = {{"label", "hard"}};
      if (press[k] != nullptr) f["heads"]["hard_soft_press"] = {{"label", press[k]}};
      p << f.dump() << "\n";
    }
  }
  auto r =
      score::score_live_run(dir + "/truth.jsonl", dir + "/predictions.jsonl", {"left", "right"});
  ASSERT_TRUE(r.ok()) << r.error().message();
  ASSERT_EQ(r->heads.size(), 2u);
  const score::HeadScore& frame = r->heads[0];
  const score::HeadScore& press = r->heads[1];
  EXPECT_EQ(frame.head, "hard_soft");
  EXPECT_EQ(frame.events.hits, 0);
  EXPECT_EQ(press.head, "hard_soft_press");
  EXPECT_EQ(press.frames.hits, 1);
  EXPECT_EQ(press.frames.total, 2);
  EXPECT_EQ(press.events.hits, 1);  // the last answer, over the whole press
  EXPECT_EQ(press.events.total, 1);
  EXPECT_EQ(press.event_labels.at("soft"), 1);
}

// A contact whose image is the open gel's (signal below kInvisibleSignalDn: a smooth flat face
// filling the gel) is no miss of the gate: counted apart, with its event.
TEST(Score, ContactsTheOpticsCannotShowAreCountedApart) {
  const ::tlvlink::testing::TempDir tmp("invisible");  // removed at the end of the test
  const std::string dir = tmp.path();
  {
    std::ofstream t(dir + "/truth.jsonl");
    t << R"({"type":"scenario","sensor":"gelsight-mini","fps":25,"frames":4,"fingers":["A","B"]})"
         "\n"
      << R"({"type":"event","id":0,"kind":"press","success":null,"material":"glass","hard_soft":"hard","rough_smooth":"smooth"})"
         "\n"
      << R"({"type":"event","id":1,"kind":"press","success":null,"material":"rock","hard_soft":"hard","rough_smooth":"rough"})"
         "\n";
    const double signal[4] = {0.3, 0.9, 12.0, 0.4};
    const int event[4] = {0, 0, 1, 1};
    for (int k = 0; k < 4; ++k) {
      t << json{{"type", "frame"}, {"finger", "A"},          {"seq", k},         {"contact", true},
                {"force_n", 20.0}, {"signal_dn", signal[k]}, {"event", event[k]}}
               .dump()
        << "\n";
    }
    std::ofstream p(dir + "/predictions.jsonl");
    for (int k = 0; k < 4; ++k) {
      p << json{{"type", "frame"},
                {"sensor", "left"},
                {"seq", k},
                {"contact", k == 2 ? "contact" : "none"}}
               .dump()
        << "\n";
    }
  }
  auto r =
      score::score_live_run(dir + "/truth.jsonl", dir + "/predictions.jsonl", {"left", "right"});
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_EQ(r->truth_contact, 1);  // the rock's visible frame
  EXPECT_EQ(r->missed_contact, 0);
  EXPECT_EQ(r->invisible_contact, 3);
  EXPECT_EQ(r->invisible_events, 1);  // the glass: no frame a camera can see
  EXPECT_EQ(r->contact_events.hits, 1);
  EXPECT_EQ(r->contact_events.total, 1);
  EXPECT_EQ(r->false_contact, 0);
  EXPECT_NE(score::format_score(*r).find("contacts the optics cannot show"), std::string::npos);
}

// Events are few: the event and grasp rates come with the Wilson 95 % interval (published values:
// 1/11 -> 1.6-37.7 %, 0/10 -> 0-27.8 %, 13/18 -> 49.1-87.5 %).
TEST(Score, EventRatesComeWithTheirInterval) {
  const auto near = [](score::Interval i, double low, double high) {
    EXPECT_NEAR(i.low, low, 5e-4);
    EXPECT_NEAR(i.high, high, 5e-4);
  };
  near(score::wilson95({1, 11}), 0.0162, 0.3774);
  near(score::wilson95({0, 10}), 0.0, 0.2775);
  near(score::wilson95({13, 18}), 0.4913, 0.8750);
  near(score::wilson95({10, 10}), 0.7225, 1.0);
  near(score::wilson95({0, 0}), 0.0, 1.0);
  score::ScoreReport r;
  r.heads.push_back({"material", {15, 650}, 0, {1, 11}, 0.273, {}});
  r.grasp_accuracy = {1, 4};
  const std::string text = score::format_score(r);
  EXPECT_NE(text.find("(1/11, 95 % CI 1.6-37.7; majority 27.3 %)"), std::string::npos) << text;
  EXPECT_NE(text.find("1/4 (25.0 %, 95 % CI 4.6-69.9;"), std::string::npos) << text;
}

}  // namespace
}  // namespace tlvlink::sim
