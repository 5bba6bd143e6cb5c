// The press head's fit from recorded presses (tools/eval press_head.h) on synthetic recordings
// whose classes share the peak and differ only in the first frame in contact: the head must
// learn them and one frame (the baseline, the peak alone) must not; short presses, unlabelled
// events and false contacts are left out; recordings of another encoder, frames without
// embeddings and a single recording are errors that say so.
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "model/tiny_models.h"
#include "support/temp_dir.h"
#include "support/test_models.h"
#include "tlvlink/eval/press_head.h"
#include "tlvlink/head_trust.h"

namespace tlvlink::testing {
namespace {

constexpr int kContactFrames = 12, kPeriod = 20;

// The tiny model (embedding dim 2) with a per-frame "hard_soft" head (its label order).
std::unique_ptr<Model> tiny_with_hard_soft() {
  TinyInt8Model m;
  m.tweak = [](quantize::ModelBuilder& b) {
    b.metadata().linear_heads.push_back({"hard_soft", {"soft", "hard"}, {1, 0, 0, 1}, {0, 0}});
  };
  return load_model(m.build());
}

std::string checksum_of(const Model& m) {
  char b[24];
  std::snprintf(b, sizeof b, "%016" PRIx64, m.metadata().provenance.content_checksum);
  return b;
}

struct Recording {
  int presses = 40;
  int short_press = -1;       // this press is seen for 3 frames only
  int unlabelled = -1;        // this event has no hard_soft label
  bool false_contact = true;  // a contact between two presses
  int drop_embedding = -1;    // this press's third frame has no embedding
};

// One scenario folder: truth.jsonl and press.jsonl. Hard presses' first frame sits at +1 on the
// embedding's first axis, soft ones' at -1; every other frame, the peak's included, is noise.
void write_recording(const std::string& dir, const std::string& checksum, uint32_t seed,
                     const Recording& r) {
  std::filesystem::create_directories(dir);
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0, 1);
  std::ofstream truth(dir + "/truth.jsonl"), pred(dir + "/press.jsonl");
  truth << R"({"type":"scenario","sensor":"digit","frames":)" << r.presses * kPeriod << "}\n";
  pred << R"({"type":"hello","model_checksum":")" << checksum << "\"}\n";
  for (int p = 0; p < r.presses; ++p) {
    const bool hard = p % 3 != 0;
    const int first = p * kPeriod, last = first + kContactFrames - 1;
    truth << R"({"type":"event","id":)" << p << R"(,"kind":"press","first_seq":)" << first
          << R"(,"last_seq":)" << last;
    if (p != r.unlabelled) truth << R"(,"hard_soft":")" << (hard ? "hard" : "soft") << '"';
    truth << "}\n";
    const int seen = p == r.short_press ? 3 : kContactFrames;
    for (int j = 0; j < kPeriod; ++j) {
      const int seq = first + j;
      const bool contact = j < seen || (r.false_contact && j == kPeriod - 2);
      pred << R"({"type":"frame_prediction","sensor":0,"frame_sequence":)" << seq
           << R"(,"contact":)" << (contact ? "true" : "false");
      if (contact && !(p == r.drop_embedding && j == 2)) {
        const float x = j == 0 ? (hard ? 1.0f : -1.0f) + 0.3f * noise(rng) : noise(rng);
        pred << R"(,"gate_score_dn":)" << 10 - std::abs(j - 6) << R"(,"embedding":[)" << x << ","
             << noise(rng) << "]";
      }
      pred << "}\n";
    }
  }
}

TEST(PressHeadFit, LearnsWhatOnlyTheSequenceShowsAndRecordsTheBaseline) {
  auto model = tiny_with_hard_soft();
  ASSERT_NE(model, nullptr);
  TempDir tmp("press_head");
  std::vector<std::string> dirs;
  for (uint32_t k = 0; k < 4; ++k) {
    dirs.push_back(tmp / ("rec" + std::to_string(k)));
    Recording r;
    r.short_press = k == 0 ? 5 : -1;
    r.unlabelled = k == 1 ? 7 : -1;
    write_recording(dirs.back(), checksum_of(*model), 100 + k, r);
  }
  eval::PressHeadOptions o;
  o.cv.bootstrap = 200;
  auto fit = eval::fit_press_head(*model, dirs, o);
  ASSERT_TRUE(fit.ok()) << fit.error().message();
  EXPECT_EQ(fit->rows.presses, 159) << "160 events, one without a label";
  EXPECT_EQ(fit->rows.short_presses, 1);
  EXPECT_EQ(fit->rows.labels.size(), 158u);
  EXPECT_EQ(fit->head.trust.n, 158);
  EXPECT_EQ(fit->rows.classes, (std::vector<std::string>{"soft", "hard"})) << "the head's order";
  // Classes apart by 2 on one axis with noise 0.3 x sqrt(2) on the difference: the head must get
  // nearly all (>= 95 %); the peak alone holds no label, so the baseline stays near the
  // majority (2/3): under 80 % (its 95 % chance range on 158 presses reaches ~74 %).
  EXPECT_GE(fit->head_cv.accuracy, 0.95);
  EXPECT_LE(fit->baseline_cv.accuracy, 0.80);
  EXPECT_EQ(fit->head_cv.groups, 4);
  const quantize::LinearHeadSpec& h = fit->head;
  EXPECT_EQ(h.name, "hard_soft_press");
  EXPECT_EQ(h.features, kPressFeatures);
  EXPECT_EQ(h.weight.size(), 2u * 2u * 2u);
  EXPECT_FLOAT_EQ(h.trust.baseline_accuracy, static_cast<float>(fit->baseline_cv.accuracy));
  EXPECT_EQ(h.trust.baseline, eval::kOneFrameBaseline);
  // Written into the model: it loads, the head is there and trusted.
  bool replaced = true;
  auto bytes = eval::model_with_press_head(*model, h, &replaced);
  ASSERT_TRUE(bytes.ok()) << bytes.error().message();
  EXPECT_FALSE(replaced);
  auto with = load_model(*bytes);
  ASSERT_NE(with, nullptr);
  ASSERT_EQ(with->metadata().press_heads.size(), 1u);
  EXPECT_TRUE(head_trusted(with->metadata().press_heads[0].trust));
  auto again = eval::model_with_press_head(*with, h, &replaced);
  ASSERT_TRUE(again.ok());
  EXPECT_TRUE(replaced) << "a press head of the same name is replaced";
  EXPECT_EQ(load_model(*again)->metadata().press_heads.size(), 1u);
  EXPECT_NE(eval::format_press_head(*fit).find("baseline (the peak alone)"), std::string::npos);
  // Two plays of the same presses: twice the rows, the same presses in the trust record.
  o.predictions = {"press.jsonl", "press.jsonl"};
  auto twice = eval::fit_press_head(*model, dirs, o);
  ASSERT_TRUE(twice.ok()) << twice.error().message();
  EXPECT_EQ(twice->rows.labels.size(), 316u);
  EXPECT_EQ(twice->head.trust.n, 158);
  EXPECT_EQ(twice->head_cv.groups, 4) << "a press's plays stay in one fold";
}

TEST(PressHeadFit, BadRecordingsAreErrorsThatSayWhat) {
  auto model = tiny_with_hard_soft();
  ASSERT_NE(model, nullptr);
  TempDir tmp("press_head_bad");
  const std::string good = tmp / "good", other = tmp / "other", holes = tmp / "holes";
  write_recording(good, checksum_of(*model), 1, {});
  write_recording(other, "0123456789abcdef", 2, {});
  Recording r;
  r.drop_embedding = 4;
  write_recording(holes, checksum_of(*model), 3, r);
  struct Case {
    std::vector<std::string> dirs;
    std::string says;
  } cases[] = {
      {{good, other}, "another encoder's"},
      {{good, holes}, "without its embedding"},
      {{good, tmp / "absent"}, "absent/truth.jsonl"},
      {{good}, "group"},  // one recording: no fold scores an unseen one
  };
  for (const Case& c : cases) {
    auto fit = eval::fit_press_head(*model, c.dirs, {});
    ASSERT_FALSE(fit.ok()) << c.says;
    EXPECT_NE(std::string(fit.error().message()).find(c.says), std::string::npos)
        << fit.error().message();
  }
  eval::PressHeadOptions named;
  named.head = "hard_soft";
  auto clash = eval::fit_press_head(*model, {good, good}, named);
  ASSERT_FALSE(clash.ok());
  EXPECT_NE(std::string(clash.error().message()).find("per-frame head"), std::string::npos);
}

}  // namespace
}  // namespace tlvlink::testing
