// `tlvlink eval` and `tlvlink heads fit` end to end on small generated sets, with the seeded
// reference encoder as the model (random but deterministic: accuracies are whatever they are, so
// the tests assert structure, determinism, and that fitted heads beat chance on the train set).

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli_run.h"
#include "support/labelled_folder.h"
#include "support/temp_dir.h"

namespace tlvlink {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using ::tlvlink::testing::CliRun;
using ::tlvlink::testing::write_colour_folder;

// stdout only unless `merge`.
// stdout only unless `merge`.
CliRun tlvlink(const std::string& args, bool merge = true) {
  return ::tlvlink::testing::run_tlvlink(
      args, merge ? ::tlvlink::testing::Stderr::kMerged : ::tlvlink::testing::Stderr::kDropped);
}

const std::string kData = TLVLINK_EVAL_DATA;
const std::string kFp32 = kData + "/ref_fp32.tlvm";
const std::string kInt8 = kData + "/ref_int8.tlvm";
const std::string kTouch = " --touch " + kData + "/t100k";
const std::string kGrasp = " --grasp " + kData + "/feel";
// A small oracle estimate keeps the test fast; its value is only checked for range.
const std::string kQuick = " -q --oracle-samples 500";

class EvalCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kFp32)) FAIL() << kFp32 << " missing: run through ctest (fixtures eval.data_*)";
  }

  json eval_json(const std::string& args) {
    const CliRun r = tlvlink("eval " + args + " --json" + kQuick, /*merge=*/false);
    EXPECT_EQ(r.exit_code, 0) << r.out;
    json j = json::parse(r.out, nullptr, false);
    EXPECT_FALSE(j.is_discarded()) << r.out;
    return j;
  }
  static const json* find(const json& report, const std::string& task, const std::string& method) {
    for (const json& r : report.at("results"))
      if (r.at("task") == task && r.at("method") == method) return &r;
    return nullptr;
  }
  ::tlvlink::testing::TempDir tmp_{"eval"};  // a fresh directory, removed with the fixture
  fs::path dir_ = tmp_.path();
};

// Deterministic, on any thread count too (the frames are embedded N at a time, each placed by
// its index: tools/eval/src/frame_pool.h).
TEST_F(EvalCli, JsonStructureAndDeterminism) {
  const json a = eval_json(kFp32 + kTouch + kGrasp);
  const json b = eval_json(kFp32 + kTouch + kGrasp + " --threads 3");
  ASSERT_EQ(a.at("reports").size(), 1u);
  const json& r = a.at("reports")[0];
  EXPECT_EQ(r.at("results"), b.at("reports")[0].at("results"));  // bit-for-bit the same cells
  EXPECT_EQ(r.at("probes"), b.at("reports")[0].at("probes"));
  ASSERT_EQ(r.at("results").size(), 12u);  // probe, model heads, zero-shot x 4 tasks
  const int64_t touch_test = r.at("touch_split").at("test_items");
  const int64_t grasp_test = r.at("grasp_split").at("test_items");
  EXPECT_EQ(r.at("touch_split").at("source"), "recorded");
  EXPECT_GT(touch_test, 0);
  EXPECT_GT(grasp_test, 0);
  for (const char* method : {"probe", "model-heads", "zero-shot"}) {
    for (const char* task : {"material", "hard_soft", "rough_smooth", "grasp"}) {
      const json* c = find(r, task, method);
      ASSERT_NE(c, nullptr) << task << " " << method;
      // The reference encoder has random linear + grasp heads and no zero-shot heads (those
      // come from the built-in text encoder): every cell is available.
      ASSERT_TRUE(c->at("available").get<bool>()) << c->dump();
      const int64_t n = c->at("n"), unlabelled = c->at("unlabelled");
      EXPECT_EQ(n + unlabelled, std::string(task) == "grasp" ? grasp_test : touch_test)
          << c->dump();
      EXPECT_GE(c->at("accuracy").get<double>(), 0.0);
      EXPECT_LE(c->at("accuracy").get<double>(), 1.0);
    }
  }
  EXPECT_EQ(find(r, "material", "probe")->at("chance"), 0.05);
  EXPECT_NE(find(r, "material", "zero-shot")->at("source").get<std::string>().find("hashing"),
            std::string::npos);
  const double oracle = r.at("grasp_oracle").at("accuracy");
  EXPECT_GT(oracle, 0.5);
  EXPECT_LE(oracle, 1.0);
  EXPECT_EQ(a.at("paper").size(), 3u);
}

TEST_F(EvalCli, TableLikeThePapers) {
  const CliRun r = tlvlink("eval " + kFp32 + kTouch + kGrasp + kQuick);
  EXPECT_RUN(r, 0);
  for (const char* s : {"linear probe", "model's heads", "zero-shot", "Material", "Hard/Soft",
                        "Rough/Smooth", "Grasp", "chance (test majority)", "grasp oracle",
                        "paper (real data)", "without curriculum"}) {
    EXPECT_NE(r.out.find(s), std::string::npos) << s << "\n" << r.out;
  }
}

// --train-jpeg: every train frame also through each JPEG quality, same labels: the fits see
// (1 + qualities) x the rows; the test split (the recorded trust) is not re-encoded.
// --train-live: one more row per train frame, through its sensor's live path.
// --touch-from-grasps: two more train rows (the fingers' frames during the grasp) per training
// grasp of a simulated Feel set.
TEST_F(EvalCli, HeadsFitOnJpegPathsAddsTrainRowsOnly) {
  const auto rows_and_n = [](const std::string& out) {
    std::smatch m;
    const std::regex re(
        R"(material\s+l2=\S+\s+train acc [0-9.]+ \(([0-9]+) rows\)\s+test acc [0-9.]+ \(n=([0-9]+)\))");
    EXPECT_TRUE(std::regex_search(out, m, re)) << out;
    return m.size() == 3 ? std::pair<long, long>{std::stol(m[1]), std::stol(m[2])}
                         : std::pair<long, long>{0, 0};
  };
  const CliRun plain =
      tlvlink("heads fit " + kFp32 + kTouch + " -q -o " + (dir_ / "plain.tlvm").string());
  EXPECT_RUN(plain, 0);
  const CliRun coded = tlvlink("heads fit " + kFp32 + kTouch + " --train-jpeg 75,90 -q -o " +
                               (dir_ / "coded.tlvm").string());
  EXPECT_RUN(coded, 0);
  const auto [plain_rows, plain_n] = rows_and_n(plain.out);
  const auto [coded_rows, coded_n] = rows_and_n(coded.out);
  EXPECT_GT(plain_rows, 0);
  EXPECT_EQ(coded_rows, 3 * plain_rows);
  EXPECT_EQ(coded_n, plain_n);
  const CliRun live =
      tlvlink("heads fit " + kFp32 + kTouch + " --train-jpeg 75 --train-live -q -o " +
              (dir_ / "live.tlvm").string());
  EXPECT_RUN(live, 0);
  const auto [live_rows, live_n] = rows_and_n(live.out);
  EXPECT_EQ(live_rows, 3 * plain_rows);
  EXPECT_EQ(live_n, plain_n);
  // Three threads (each re-encoding, rendering the live view of and embedding its own frames):
  // the same file, byte for byte.
  const CliRun threads =
      tlvlink("heads fit " + kFp32 + kTouch + " --train-jpeg 75 --train-live -q --threads 3 -o " +
              (dir_ / "live3.tlvm").string());
  EXPECT_RUN(threads, 0);
  // The reports alike but for the "wrote PATH" line.
  EXPECT_EQ(threads.out.substr(threads.out.find('\n')), live.out.substr(live.out.find('\n')));
  std::ifstream one(dir_ / "live.tlvm", std::ios::binary),
      three(dir_ / "live3.tlvm", std::ios::binary);
  EXPECT_TRUE(std::equal(std::istreambuf_iterator<char>(one), std::istreambuf_iterator<char>(),
                         std::istreambuf_iterator<char>(three), std::istreambuf_iterator<char>()))
      << "--threads 3 wrote another file than one thread";
  const CliRun grasped = tlvlink("heads fit " + kFp32 + kTouch + " --touch-from-grasps " + kData +
                                 "/feel -q -o " + (dir_ / "grasped.tlvm").string());
  EXPECT_RUN(grasped, 0);
  const auto [grasped_rows, grasped_n] = rows_and_n(grasped.out);
  EXPECT_GT(grasped_rows, plain_rows);
  EXPECT_EQ((grasped_rows - plain_rows) % 2, 0);    // both fingers of every grasp
  EXPECT_LE(grasped_rows - plain_rows, 2 * 8 * 3);  // the fixture's 8 objects x 3 grasps
  EXPECT_EQ(grasped_n, plain_n);
  const CliRun no_touch = tlvlink("heads fit " + kFp32 + kGrasp + " --touch-from-grasps " + kData +
                                  "/feel -q -o " + (dir_ / "r.tlvm").string());
  EXPECT_RUN(no_touch, 2);
  EXPECT_NE(no_touch.out.find("--touch-from-grasps needs --touch"), std::string::npos)
      << no_touch.out;
  const CliRun bad = tlvlink("heads fit " + kFp32 + kTouch + " --train-jpeg 0 -q -o " +
                             (dir_ / "bad.tlvm").string());
  EXPECT_RUN(bad, 2);  // an invalid argument
  EXPECT_NE(bad.out.find("--train-jpeg 0"), std::string::npos) << bad.out;
  // --view-weight: one head's own weight, saying which weight it got and how often its
  // validation frames kept their answer through the codec; --only: that head alone is refitted,
  // the model's others are kept (the material head scores exactly as before).
  const std::string plain_model = (dir_ / "plain.tlvm").string();
  const CliRun steady = tlvlink("heads fit " + plain_model + kTouch +
                                " --only hard_soft --train-jpeg 75,90 --view-weight hard_soft=10 "
                                "--no-zero-shot -q -o " +
                                (dir_ / "steady.tlvm").string());
  EXPECT_RUN(steady, 0);
  EXPECT_TRUE(std::regex_search(
      steady.out, std::regex(R"(hard_soft [^\n]*view weight 10 \(validation: [0-9.]+ %)")))
      << steady.out;
  EXPECT_FALSE(std::regex_search(steady.out, std::regex(R"(\n  material +l2=)"))) << steady.out;
  // The live path's views alone are second views too.
  const CliRun live_only = tlvlink("heads fit " + plain_model + kTouch +
                                   " --only rough_smooth --train-live --view-weight 3 "
                                   "--no-zero-shot -q -o " +
                                   (dir_ / "live_only.tlvm").string());
  EXPECT_RUN(live_only, 0);
  EXPECT_TRUE(std::regex_search(
      live_only.out, std::regex(R"(rough_smooth [^\n]*view weight 3 \(validation: [0-9.]+ %)")))
      << live_only.out;
  const json before = eval_json(plain_model + kTouch).at("reports")[0];
  const json after = eval_json((dir_ / "steady.tlvm").string() + kTouch).at("reports")[0];
  EXPECT_EQ(find(before, "material", "model-heads")->at("correct"),
            find(after, "material", "model-heads")->at("correct"));
  for (const auto& [flags, named] : std::vector<std::pair<std::string, std::string>>{
           {" --view-weight 3", "--train-jpeg"},
           {" --train-jpeg 75 --view-weight grasp=3", "grasp=3"},
           {" --train-jpeg 75 --view-weight rugh=3", "rugh=3"},
           {" --train-jpeg 75 --view-weight 3 --min-view-agreement 0.9", "several"},
           {" --only rugh", "--only rugh"}}) {
    const CliRun refused =
        tlvlink("heads fit " + kFp32 + kTouch + flags + " -q -o " + (dir_ / "r.tlvm").string());
    EXPECT_RUN(refused, 2);
    EXPECT_NE(refused.out.find(named), std::string::npos) << flags << "\n" << refused.out;
    EXPECT_FALSE(fs::exists(dir_ / "r.tlvm")) << flags;
  }
}

TEST_F(EvalCli, HeadsFitWritesAModelThatRunsIdenticallyAndBeatsChance) {
  const std::string out = (dir_ / "heads.tlvm").string();
  const CliRun fit = tlvlink("heads fit " + kFp32 + kTouch + kGrasp + " -q -o " + out);
  EXPECT_RUN(fit, 0);
  ASSERT_TRUE(fs::exists(out));
  // Train-set accuracy of each fitted head against its chance level.
  const std::pair<const char*, double> chance[] = {
      {"material", 0.05}, {"hard_soft", 0.5}, {"rough_smooth", 0.5}, {"grasp", 0.5}};
  for (const auto& [task, level] : chance) {
    std::smatch m;
    const std::regex re(std::string(task) + R"(\s+l2=\S+\s+train acc ([0-9.]+))");
    ASSERT_TRUE(std::regex_search(fit.out, m, re)) << task << "\n" << fit.out;
    EXPECT_GT(std::stod(m[1]), level) << task << "\n" << fit.out;
  }
  // Same graph: the embedded golden pairs still verify.
  EXPECT_RUN(tlvlink("verify " + out), 0);
  // The stored heads score exactly what the freshly fitted probes score (same embeddings,
  // deterministic fit). The zero-shot heads the fit kept (those beating their test set's
  // majority class; the others are printed as "removed") now come from the model.
  const json j = eval_json(out + kTouch + kGrasp);
  const json& r = j.at("reports")[0];
  int from_model = 0;
  for (const char* task : {"material", "hard_soft", "rough_smooth", "grasp"}) {
    EXPECT_EQ(find(r, task, "probe")->at("correct"), find(r, task, "model-heads")->at("correct"))
        << task;
    const std::string source = find(r, task, "zero-shot")->at("source").get<std::string>();
    if (source.find("model zero-shot") != std::string::npos) ++from_model;
  }
  const std::regex zero_shot_line(R"(zero-shot head '[^']+': [^\n]*)");
  int kept = 0, listed = 0;
  for (auto it = std::sregex_iterator(fit.out.begin(), fit.out.end(), zero_shot_line);
       it != std::sregex_iterator(); ++it, ++listed) {
    if (it->str().find("removed") == std::string::npos) ++kept;
  }
  EXPECT_EQ(listed, 4) << fit.out;
  EXPECT_EQ(from_model, kept) << fit.out;
}

TEST_F(EvalCli, CompareFp32AndInt8) {
  const json j = eval_json(kFp32 + " --compare " + kInt8 + kTouch + kGrasp);
  ASSERT_EQ(j.at("reports").size(), 2u);
  EXPECT_EQ(j.at("reports")[1].at("results").size(), 12u);
  const CliRun t = tlvlink("eval " + kFp32 + " --compare " + kInt8 + kTouch + kQuick);
  EXPECT_RUN(t, 0);
  EXPECT_NE(t.out.find("difference [2] - [1]"), std::string::npos) << t.out;
}

TEST_F(EvalCli, TouchAndGoAndBeforeAfterGraspFeatures) {
  const json j =
      eval_json(kFp32 + " --touch " + kData + "/tag" + kGrasp + " --grasp-features before-after");
  const json& r = j.at("reports")[0];
  EXPECT_EQ(r.at("grasp_features"), "before-after");
  EXPECT_TRUE(find(r, "material", "probe")->at("available").get<bool>());
  EXPECT_EQ(r.at("touch_split").at("source"), "recorded");
  EXPECT_EQ(r.at("touch_split").at("format"), "touch_and_go");
  EXPECT_EQ(r.at("grasp_split").at("format"), "feel_repacked");
}

TEST_F(EvalCli, FeelHdf5) {
  const json j = eval_json(kFp32 + " --grasp " + kData + "/feel_h5");
  const json& r = j.at("reports")[0];
  EXPECT_EQ(r.at("grasp_split").at("format"), "feel_hdf5");
  EXPECT_EQ(r.at("grasp_split").at("source"), "recorded");
  EXPECT_EQ(r.at("grasp_split").at("test_groups"), 1);  // round(4 objects * 0.2)
  EXPECT_EQ(find(r, "grasp", "zero-shot")->at("n"), 2);
  EXPECT_TRUE(r.at("touch_split").is_null());
}

// The reference executor is slow: a few items per split (--max-*) and a forced hash split.
TEST_F(EvalCli, ReferenceExecutorCapsAndResplit) {
  const json j = eval_json(kFp32 + kTouch + kGrasp +
                           " --executor reference --max-touch 3 --max-grasp 2 --resplit 0.5");
  const json& r = j.at("reports")[0];
  EXPECT_EQ(r.at("executor"), "reference");
  EXPECT_LE(r.at("touch_split").at("train_items").get<int64_t>(), 3);
  EXPECT_LE(r.at("touch_split").at("test_items").get<int64_t>(), 3);
  EXPECT_LE(r.at("grasp_split").at("test_items").get<int64_t>(), 2);
  EXPECT_EQ(r.at("touch_split").at("source"), "hash(test_fraction=0.5, seed=0)");
}

TEST_F(EvalCli, BadInputsGiveClearErrors) {
  CliRun r = tlvlink("eval " + kFp32 + " --touch " + (dir_ / "missing").string());
  EXPECT_RUN(r, 1);
  EXPECT_NE(r.out.find("does not exist"), std::string::npos) << r.out;
  r = tlvlink("eval " + kFp32);  // no dataset
  EXPECT_RUN(r, 2);
  r = tlvlink("eval " + kFp32 + " -q --touch " + kData + "/t100k_nolabels");
  EXPECT_RUN(r, 1);
  EXPECT_NE(r.out.find("no material, hard/soft or rough/smooth label"), std::string::npos) << r.out;
  r = tlvlink("eval " + (dir_ / "nope.tlvm").string() + kTouch);
  EXPECT_RUN(r, 1);
  r = tlvlink("heads fit " + kFp32 + kTouch);  // no -o
  EXPECT_RUN(r, 2);
  // An existing output is refused before any fitting and left as it was.
  const fs::path mine = dir_ / "mine.tlvm";
  { std::ofstream(mine) << "not ours"; }
  r = tlvlink("heads fit " + kFp32 + kTouch + kGrasp + " -q -o " + mine.string());
  EXPECT_RUN(r, 1);
  EXPECT_NE(r.out.find("exists; pass --overwrite"), std::string::npos) << r.out;
  std::ifstream kept(mine);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), {}), "not ours");
  r = tlvlink("eval " + kFp32 + " --touch " + kData + "/feel");  // a grasp set given as touch
  EXPECT_RUN(r, 1);
  EXPECT_NE(r.out.find("not a touch dataset"), std::string::npos) << r.out;
}

TEST_F(EvalCli, HeadsFitImagesAddsAValidatedHeadAndEvalScoresIt) {
  const fs::path frames = dir_ / "frames";
  write_colour_folder(frames);
  const std::string out = (dir_ / "colour.tlvm").string();
  const CliRun fit = tlvlink("heads fit " + kInt8 + " --images " + frames.string() +
                             " --head colour --learning-curve -o " + out);
  EXPECT_RUN(fit, 0);
  for (const char* s : {"24 in 2 classes, 6 groups (grouping: subfolders)", "grouped 3-fold",
                        "baseline (32x24 pixels)", "k=1", "k=2", "head 'colour' (added)"}) {
    EXPECT_NE(fit.out.find(s), std::string::npos) << s << "\n" << fit.out;
  }
  // Colour is in the pixels: the baseline reads it perfectly, so the head cannot beat it and is
  // recorded untrusted (left out of the daemon's default output) whatever its own accuracy.
  EXPECT_NE(fit.out.find("does not beat the pixel baseline"), std::string::npos) << fit.out;
  EXPECT_RUN(tlvlink("verify " + out), 0);  // same graph, golden pairs still pass
  const CliRun shown = tlvlink("inspect " + out);
  EXPECT_NE(shown.out.find("baseline 100.0 %"), std::string::npos) << shown.out;
  EXPECT_NE(shown.out.find("6 groups"), std::string::npos) << shown.out;

  // Fitting again over the same name replaces it, and only with --overwrite.
  const CliRun refused =
      tlvlink("heads fit " + out + " --images " + frames.string() + " --head colour -o " + out);
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.out.find("exists; pass --overwrite"), std::string::npos) << refused.out;
  const std::string again = (dir_ / "again.tlvm").string();
  const CliRun replaced =
      tlvlink("heads fit " + out + " --images " + frames.string() + " --head colour -o " + again);
  EXPECT_RUN(replaced, 0);
  EXPECT_NE(replaced.out.find("head 'colour' (replaced)"), std::string::npos) << replaced.out;

  // eval --images: the head on frames (its own here), beside what its record says.
  const CliRun scored = tlvlink("eval " + out + " --images " + frames.string() + " --head colour");
  EXPECT_RUN(scored, 0);
  for (const char* s : {"24 frames, 6 groups", "accuracy", "recorded: untrusted", "answers:"}) {
    EXPECT_NE(scored.out.find(s), std::string::npos) << s << "\n" << scored.out;
  }
  const CliRun wrong_label =
      tlvlink("eval " + kInt8 + " --images " + frames.string() + " --head rough_smooth");
  EXPECT_NE(wrong_label.exit_code, 0);
  EXPECT_NE(wrong_label.out.find("'cool' is not a label of head 'rough_smooth'"), std::string::npos)
      << wrong_label.out;
}

TEST_F(EvalCli, HeadsFitImagesRefusesWhatItCannotValidate) {
  const fs::path frames = dir_ / "one_object";
  write_colour_folder(frames, 1);
  const CliRun one = tlvlink("heads fit " + kInt8 + " --images " + frames.string() +
                             " --head colour -o " + (dir_ / "x.tlvm").string());
  EXPECT_NE(one.exit_code, 0);
  EXPECT_NE(one.out.find("class 'cool' has frames of one group only"), std::string::npos)
      << one.out;
  EXPECT_FALSE(fs::exists(dir_ / "x.tlvm"));
  const CliRun both = tlvlink("heads fit " + kInt8 + " --images " + frames.string() + kTouch +
                              " --head colour -o " + (dir_ / "y.tlvm").string());
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.out.find("give one or the other"), std::string::npos) << both.out;
  const CliRun nameless = tlvlink("heads fit " + kInt8 + " --images " + frames.string() + " -o " +
                                  (dir_ / "z.tlvm").string());
  EXPECT_NE(nameless.exit_code, 0);
  EXPECT_NE(nameless.out.find("--head NAME"), std::string::npos) << nameless.out;
}

// A 320x240 PPM: grey 120 with +-3 DN of noise, `blob` adds a 40x40 press of +30 DN.
void write_gel(const fs::path& path, int offset, bool blob, int width = 320, int height = 240) {
  uint32_t state = static_cast<uint32_t>(offset * 7919 + (blob ? 17 : 3));
  std::ofstream out(path, std::ios::binary);
  out << "P6\n" << width << " " << height << "\n255\n";
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const bool pressed = blob && x >= 140 && x < 180 && y >= 100 && y < 140;
      for (int c = 0; c < 3; ++c) {
        state = state * 1664525u + 1013904223u;
        const int noise = static_cast<int>((state >> 24) % 7) - 3;
        out.put(static_cast<char>(120 + offset + noise + (pressed ? 30 : 0)));
      }
    }
  }
}

TEST_F(EvalCli, ContactRunsTheBoardsGateOnYourFrames) {
  write_gel(dir_ / "ref.ppm", 0, false);
  write_gel(dir_ / "idle.ppm", 1, false);  // 1 DN of drift, fresh noise
  write_gel(dir_ / "press.ppm", 0, true);
  const CliRun r = tlvlink("contact -r " + (dir_ / "ref.ppm").string() + " " +
                           (dir_ / "idle.ppm").string() + " " + (dir_ / "press.ppm").string());
  EXPECT_RUN(r, 0);
  EXPECT_NE(r.out.find("contact above 4.00 DN"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("none     score"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 of 2 frames in contact"), std::string::npos) << r.out;
  const std::regex press(R"(contact\s+score\s+([0-9.]+) DN\s+\S*press.ppm)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, press)) << r.out;
  EXPECT_NEAR(std::stod(m[1]), 30.0, 4.0);  // the press's 30 DN, less block-edge and noise
  // Two references: their spread sets the noise, the threshold follows it.
  const CliRun two = tlvlink("contact -r " + (dir_ / "ref.ppm").string() + " -r " +
                             (dir_ / "idle.ppm").string() + " " + (dir_ / "press.ppm").string());
  EXPECT_RUN(two, 0);
  EXPECT_NE(two.out.find("reference: 2 frame(s)"), std::string::npos) << two.out;
  write_gel(dir_ / "small.ppm", 0, false, 160, 120);
  const CliRun other =
      tlvlink("contact -r " + (dir_ / "ref.ppm").string() + " " + (dir_ / "small.ppm").string());
  EXPECT_NE(other.exit_code, 0);
  EXPECT_NE(other.out.find("the references' is 320x240"), std::string::npos) << other.out;
}

TEST_F(EvalCli, HeadsFitRecordingsDecodesThemAsTheDaemonDoes) {
  // Each object's frames as a camera recording (what `tlvlink record` and tlvlinkd's recorder
  // write), labelled per recording; frames held for 2 (repeats) count once.
  const fs::path frames = dir_ / "frames";
  write_colour_folder(frames);
  std::ofstream labels(dir_ / "labels.tsv");
  labels << "# recording, class, from, to\n";
  for (const char* cls : {"warm", "cool"}) {
    for (int o = 0; o < 3; ++o) {
      const std::string name = std::string(cls) + std::to_string(o) + ".tlvraw";
      const CliRun rec =
          tlvlink("record --images " + (frames / cls / ("object" + std::to_string(o))).string() +
                  " --hold 2 -o " + (dir_ / name).string());
      ASSERT_RUN(rec, 0);
      labels << name << "\t" << cls << (o == 0 ? "\t0\t0.2" : "")
             << "\n";  // 0.2 s: 5 records, 3 frames (4 x 4 + 2 x 3 = 22)
    }
  }
  labels.close();
  const std::string l = (dir_ / "labels.tsv").string();
  const CliRun fit =
      tlvlink("heads fit " + kInt8 + " --recordings " + l +
              " --sensor gelsight-mini-processed --head colour -o " + (dir_ / "rec.tlvm").string());
  EXPECT_RUN(fit, 0);
  for (const char* s : {"22 in 2 classes, 6 groups (grouping: recordings)",
                        "read as 22 as gelsight-mini-processed 320x240"}) {
    EXPECT_NE(fit.out.find(s), std::string::npos) << s << "\n" << fit.out;
  }
  // 320x240 MJPEG is both a processed Mini's and an R1.5's stream: the sensor must be named.
  const CliRun ambiguous = tlvlink("heads fit " + kInt8 + " --recordings " + l +
                                   " --head colour -o " + (dir_ / "x.tlvm").string());
  EXPECT_NE(ambiguous.exit_code, 0);
  EXPECT_NE(ambiguous.out.find("name the sensor (--sensor)"), std::string::npos) << ambiguous.out;
  std::ofstream(dir_ / "bad.tsv") << "warm0.tlvraw\twarm\n# next\ncool0.tlvraw\tcool\t2\t1\n";
  const CliRun bad = tlvlink("heads fit " + kInt8 + " --recordings " + (dir_ / "bad.tsv").string() +
                             " --head colour -o " + (dir_ / "y.tlvm").string());
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.out.find("bad.tsv:3"), std::string::npos) << bad.out;
  std::ofstream(dir_ / "empty.tsv") << "warm0.tlvraw\twarm\t50\t60\ncool0.tlvraw\tcool\n";
  const CliRun empty =
      tlvlink("heads fit " + kInt8 + " --recordings " + (dir_ / "empty.tsv").string() +
              " --head colour -o " + (dir_ / "z.tlvm").string());
  EXPECT_NE(empty.exit_code, 0);
  EXPECT_NE(empty.out.find("empty.tsv:1: no frame"), std::string::npos) << empty.out;
}

}  // namespace
}  // namespace tlvlink
