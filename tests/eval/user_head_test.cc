// Heads of the user's own (issue 30): the labelled-folder reader, grouped cross-validation
// (no scored row's group is ever fitted on; L2 chosen inside the fitting folds), the learning
// curve, and on the real GelSight Mini billets beside the repository (skipped where ../shared
// is absent) the roughness target with the shipped int8 model.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/temp_dir.h"
#include "tlvlink/eval/contact_check.h"
#include "tlvlink/eval/grouped_cv.h"
#include "tlvlink/eval/labelled_frames.h"
#include "tlvlink/eval/trust.h"
#include "tlvlink/eval/user_head.h"
#include "tlvlink/head_trust.h"
#include "tlvlink/model.h"

namespace tlvlink::eval {
namespace {

namespace fs = std::filesystem;

// Rows of `groups` groups, `per_group` rows each, dim `dim`.
struct Synthetic {
  std::vector<float> x;
  std::vector<int32_t> labels;
  std::vector<std::string> groups;
  int32_t dim = 0;
  GroupedRows rows() const { return {x, dim, labels, 2, groups}; }
};

// Each group has its own random label and a feature that names the group (one-hot): a model can
// memorise groups but nothing carries over to an unseen one.
Synthetic memorisable(int32_t groups, int32_t per_group, uint64_t seed) {
  Synthetic s;
  s.dim = groups;
  std::mt19937_64 rng(seed);
  for (int32_t g = 0; g < groups; ++g) {
    const int32_t label = g % 2;  // balanced classes
    for (int32_t i = 0; i < per_group; ++i) {
      for (int32_t d = 0; d < groups; ++d)
        s.x.push_back(d == g ? 1.0f : 0.0f + 0.01f * std::normal_distribution<float>()(rng));
      s.labels.push_back(label);
      s.groups.push_back("object" + std::to_string(g));
    }
  }
  return s;
}

// Two classes apart along feature 0 (+-2 with unit noise elsewhere), groups of mixed offsets.
Synthetic separable(int32_t groups, int32_t per_group, uint64_t seed) {
  Synthetic s;
  s.dim = 4;
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> noise;
  for (int32_t g = 0; g < groups; ++g) {
    const int32_t label = g % 2;
    for (int32_t i = 0; i < per_group; ++i) {
      s.x.push_back((label ? 3.0f : -3.0f) + 0.3f * noise(rng));
      for (int32_t d = 1; d < s.dim; ++d) s.x.push_back(noise(rng));
      s.labels.push_back(label);
      s.groups.push_back("g" + std::to_string(g));
    }
  }
  return s;
}

TEST(GroupedCv, GroupsNeverStraddleFitAndScore) {
  // Memorising groups must not pay: scored on unseen groups, a group-identity feature says
  // nothing, so accuracy stays near chance. Scored frame by frame (every row its own group,
  // which is what a leaky split would do) the same data reads as near perfect.
  const Synthetic s = memorisable(12, 6, 1);
  auto grouped = cross_validate(s.rows(), {});
  ASSERT_TRUE(grouped.ok()) << grouped.error().message();
  EXPECT_LE(grouped->accuracy, 0.65) << "a fold scored rows of a group it was fitted on";
  std::vector<std::string> own(s.groups.size());
  for (size_t i = 0; i < own.size(); ++i) own[i] = "row" + std::to_string(i);
  auto leaky = cross_validate({s.x, s.dim, s.labels, 2, own}, {});
  ASSERT_TRUE(leaky.ok()) << leaky.error().message();
  EXPECT_GE(leaky->accuracy, 0.95);
}

TEST(GroupedCv, SeparableClassesAreFoundWithTheirInterval) {
  const Synthetic s = separable(8, 5, 2);
  auto cv = cross_validate(s.rows(), {});
  ASSERT_TRUE(cv.ok()) << cv.error().message();
  EXPECT_EQ(cv->folds, 4);  // 4 groups per class bound the 5 folds asked
  EXPECT_EQ(cv->n, 40);
  EXPECT_EQ(cv->groups, 8);
  EXPECT_DOUBLE_EQ(cv->accuracy, 1.0);
  EXPECT_DOUBLE_EQ(cv->balanced_accuracy, 1.0);
  EXPECT_DOUBLE_EQ(cv->majority, 0.5);
  EXPECT_LE(cv->ci_low, cv->accuracy);
  EXPECT_GE(cv->ci_high, cv->accuracy);
  EXPECT_EQ(cv->fold_l2.size(), 4u);
  EXPECT_EQ(cv->class_rows, (std::vector<int64_t>{20, 20}));
  EXPECT_EQ(cv->class_groups, (std::vector<int64_t>{4, 4}));
  auto again = cross_validate(s.rows(), {});
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->predicted, cv->predicted);  // deterministic
}

TEST(GroupedCv, IntervalIsOverGroupsNotFrames) {
  // 6 groups, one of them all wrong: resampling groups gives a wide interval; resampling the
  // same rows as if independent (one group per row) a narrower one.
  std::vector<uint8_t> right(60, 1);
  std::vector<std::string> groups(60), rows(60);
  for (size_t i = 0; i < 60; ++i) {
    groups[i] = "g" + std::to_string(i / 10);
    rows[i] = "r" + std::to_string(i);
    if (i < 10) right[i] = 0;
  }
  const Interval by_group = group_bootstrap_interval(right, groups, 0);
  const Interval by_row = group_bootstrap_interval(right, rows, 0);
  EXPECT_LE(by_group.low, 5.0 / 6.0);
  EXPECT_GE(by_group.high, 5.0 / 6.0);
  EXPECT_GT(by_group.high - by_group.low, 1.5 * (by_row.high - by_row.low));
}

TEST(GroupedCv, AClassSeenInOneGroupOnlyIsAnErrorNamingIt) {
  Synthetic s = separable(4, 3, 3);
  for (size_t i = 0; i < s.groups.size(); ++i)
    if (s.labels[i] == 1) s.groups[i] = "the-only-rough-billet";
  const std::vector<std::string> names = {"smooth", "rough"};
  auto cv = cross_validate({s.x, s.dim, s.labels, 2, s.groups, names}, {});
  ASSERT_FALSE(cv.ok());
  EXPECT_NE(std::string(cv.error().message()).find("'rough'"), std::string::npos)
      << cv.error().message();
  EXPECT_NE(std::string(cv.error().message()).find("the-only-rough-billet"), std::string::npos);
}

TEST(GroupedCv, LearningCurveTriesEveryChoiceWhenFew) {
  const Synthetic s = separable(6, 4, 4);  // 3 groups per class
  auto curve = learning_curve(s.rows(), {}, 30);
  ASSERT_TRUE(curve.ok()) << curve.error().message();
  ASSERT_EQ(curve->size(), 2u);     // k = 1, 2
  EXPECT_EQ((*curve)[0].draws, 9);  // C(3,1)^2
  EXPECT_EQ((*curve)[1].draws, 9);  // C(3,2)^2
  EXPECT_DOUBLE_EQ((*curve)[0].mean_test_rows, 16.0);
  EXPECT_DOUBLE_EQ((*curve)[1].mean_test_rows, 8.0);
  // Classes 6 noise-widths apart: every draw finds them; 3 noise features can cost a frame or
  // two when only 4 rows per class are fitted.
  for (const CurvePoint& p : *curve) {
    EXPECT_GE(p.min, 0.75);
    EXPECT_GE(p.mean, 0.9);
  }
}

// --- the folder reader ---

void touch_file(const fs::path& p, const std::string& text = "x") {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

TEST(LabelledFolder, GroupsFromSubfoldersOrTheGroupsFileOrNone) {
  testing::TempDir t;
  const fs::path a = fs::path(t.path()) / "a";
  touch_file(a / "smooth/b1/f1.png");
  touch_file(a / "smooth/b1/f2.PNG");
  touch_file(a / "rough/b2/f1.jpg");
  touch_file(a / "rough/b2/notes.txt");
  auto sub = read_labelled_folder(a.string());
  ASSERT_TRUE(sub.ok()) << sub.error().message();
  EXPECT_EQ(sub->classes, (std::vector<std::string>{"rough", "smooth"}));
  EXPECT_EQ(sub->grouping, Grouping::kSubfolders);
  ASSERT_EQ(sub->frames.size(), 3u);
  EXPECT_EQ(sub->frames[0].group, "rough/b2");
  EXPECT_EQ(sub->frames[0].label, 0);
  EXPECT_EQ(sub->frames[1].relative, "smooth/b1/f1.png");
  ASSERT_EQ(sub->skipped.size(), 1u);  // notes.txt, named
  EXPECT_NE(sub->skipped[0].find("notes.txt"), std::string::npos);

  const fs::path b = fs::path(t.path()) / "b";
  touch_file(b / "slip/e1.png");
  touch_file(b / "no_slip/e2.png");
  touch_file(b / "groups.tsv", "# object of each frame\nslip/e1.png\tmug\nno_slip/e2.png\tmug\n");
  auto listed = read_labelled_folder(b.string());
  ASSERT_TRUE(listed.ok()) << listed.error().message();
  EXPECT_EQ(listed->grouping, Grouping::kGroupsFile);
  EXPECT_EQ(listed->group_count(), 1);

  const fs::path c = fs::path(t.path()) / "c";
  touch_file(c / "x/1.png");
  touch_file(c / "y/2.png");
  auto none = read_labelled_folder(c.string());
  ASSERT_TRUE(none.ok()) << none.error().message();
  EXPECT_EQ(none->grouping, Grouping::kNone);
  EXPECT_EQ(none->group_count(), 2);
}

TEST(LabelledFolder, EveryMistakeIsAnErrorNamingWhere) {
  testing::TempDir t;
  struct Case {
    const char* what;
    std::vector<std::pair<std::string, std::string>> files;
    std::string expected;  // a part of the message
  };
  const Case cases[] = {
      {"one class", {{"only/1.png", "x"}}, "1 class folder"},
      {"empty class", {{"a/1.png", "x"}, {"b/readme.txt", "x"}}, "/b: no frames"},
      {"bad groups line",
       {{"a/1.png", "x"}, {"b/2.png", "x"}, {"groups.tsv", "a/1.png\tg\nb/2.png g2\n"}},
       "groups.tsv:2"},
      {"unlisted frame",
       {{"a/1.png", "x"}, {"b/2.png", "x"}, {"groups.tsv", "a/1.png\tg\n"}},
       "b/2.png is not listed"},
      {"listed, absent",
       {{"a/1.png", "x"}, {"b/2.png", "x"}, {"groups.tsv", "a/1.png\tg\nb/2.png\tg\nb/3.png\tg\n"}},
       "lists b/3.png"},
      {"twice",
       {{"a/1.png", "x"}, {"b/2.png", "x"}, {"groups.tsv", "a/1.png\tg\na/1.png\th\n"}},
       "listed twice"},
      {"mixed layout", {{"a/g/1.png", "x"}, {"b/2.png", "x"}}, "some frames are in group"},
  };
  int i = 0;
  for (const Case& c : cases) {
    const fs::path dir = fs::path(t.path()) / std::to_string(i++);
    fs::create_directories(dir);
    for (const auto& [name, text] : c.files) touch_file(dir / name, text);
    auto r = read_labelled_folder(dir.string());
    ASSERT_FALSE(r.ok()) << c.what;
    EXPECT_NE(std::string(r.error().message()).find(c.expected), std::string::npos)
        << c.what << ": " << r.error().message();
  }
  EXPECT_FALSE(read_labelled_folder((fs::path(t.path()) / "absent").string()).ok());
}

// --- real frames ---

constexpr const char* kShipped = TLVLINK_SOURCE_DIR "/firmware/models/touch-tiny-int8.tlvm";
constexpr const char* kBillets =
    TLVLINK_SOURCE_DIR "/../shared/real-frames/gelsight-contrastive-learning";

TEST(UserHeadRealFrames, RoughnessOnGelSightMiniBilletsBeatsPixelsOnUnseenBillets) {
  if (!fs::exists(kBillets)) GTEST_SKIP() << kBillets << " absent: the real frames are not here";
  testing::TempDir t;
  // The ImageFolder layout as a user would make it: one folder per billet (its group).
  for (int b = 1; b <= 3; ++b) {
    for (const auto& [cls, folder] :
         {std::pair{"rough", "billet_captures"}, std::pair{"smooth", "billet_captures_grinded"}}) {
      const fs::path group = fs::path(t.path()) / cls / ("billet" + std::to_string(b));
      fs::create_directories(group);
      for (int frame : {1, 5, 9, 13}) {
        const std::string name =
            "billet" + std::to_string(b) + "_camera_" + std::to_string(frame) + ".png";
        fs::create_symlink(fs::path(kBillets) / folder / name, group / name);
      }
    }
  }
  auto frames = read_labelled_folder(t.path());
  ASSERT_TRUE(frames.ok()) << frames.error().message();
  auto model = Model::load_file(kShipped);
  ASSERT_TRUE(model.ok()) << model.error().message();
  UserHeadOptions o;
  o.head = "roughness";
  o.learning_curve = true;
  auto fit = fit_user_head(**model, *frames, o);
  ASSERT_TRUE(fit.ok()) << fit.error().message();
  std::printf("%s", format_user_head(*frames, *fit).c_str());
  // Issue 30's target: >= 90 % on unseen billets from <= 3 labelled billets per class. Measured
  // with the shipped files: 95.8 % (3-fold, 2 per class fitted), 94.4 % from one per class; the
  // pixel baseline 70.8 %. Deterministic for a given model; the bound leaves one billet's worth
  // of frames (4 of 24) for a re-made model.
  EXPECT_GE(fit->head_cv.accuracy, 0.90);
  ASSERT_FALSE(fit->head_curve.empty());
  EXPECT_GE(fit->head_curve[0].mean, 0.85);
  EXPECT_GT(fit->head_cv.accuracy, fit->baseline_cv.accuracy);
  EXPECT_TRUE(head_trusted(trust_view(fit->head.trust)));
  auto bytes = model_with_user_head(**model, fit->head);
  ASSERT_TRUE(bytes.ok()) << bytes.error().message();
  auto written = Model::load(*bytes);
  ASSERT_TRUE(written.ok()) << written.error().message();
  const auto& heads = (*written)->metadata().linear_heads;
  ASSERT_FALSE(heads.empty());
  EXPECT_EQ(heads.back().name, "roughness");
  EXPECT_EQ(heads.back().trust.groups, 6);
  EXPECT_NEAR(heads.back().trust.accuracy, fit->head_cv.accuracy, 1e-6);
}

constexpr const char* kRealFrames = TLVLINK_SOURCE_DIR "/../shared/real-frames";

TEST(ContactCheckRealFrames, EveryPressOfTheReferenceSessionsIsSeen) {
  if (!fs::exists(kRealFrames))
    GTEST_SKIP() << kRealFrames << " absent: the real frames are not here";
  // Presses of calibration balls on a GelSight Mini, a GelSlim and a GelSight-type marker sensor,
  // each session with its own no-contact reference (colour cast, markers, vignetting included):
  // the board's gate with the daemon's defaults sees every one (issue 30: >= 98 %).
  const fs::path root(kRealFrames);
  struct Session {
    const char* dir;
    const char* reference;
  };
  const Session sessions[] = {
      {"16741-Proj-ShapeMap3D-GelSightMini/Taxim/data/Gel/11_19_2023/calib_ball", "frame_0.png"},
      {"gelslim/Software/GUI/GelSlim/test_data", "ref.jpg"},
      {"gelsight_heightmap_reconstruction/python_version/test_data", "ref.jpg"},
  };
  int presses = 0;
  for (const Session& s : sessions) {
    std::vector<std::string> frames;
    for (const auto& e : fs::directory_iterator(root / s.dir))
      if (e.path().filename() != s.reference) frames.push_back(e.path().string());
    ASSERT_FALSE(frames.empty()) << s.dir;
    auto check = check_contact({(root / s.dir / s.reference).string()}, frames, {});
    ASSERT_TRUE(check.ok()) << check.error().message();
    for (const ContactCheckFrame& f : check->frames) {
      EXPECT_TRUE(f.contact) << f.path << " score " << f.score_dn << " DN";
      ++presses;
    }
  }
  EXPECT_GE(presses, 30);
}

}  // namespace
}  // namespace tlvlink::eval
