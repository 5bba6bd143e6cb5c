// The CI smoke training (ctest label `trainer`): through the real `tlvlink` binary, generate a
// small simulator set, train `tiny` briefly, check the loss decreased, export, and check the
// runtime reproduces libtorch on held-out frames. Plus the CLI's answers to bad arguments.

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/cli_run.h"
#include "tlvlink/executor.h"
#include "tlvlink/model.h"
#include "trainer/trainer_support.h"

namespace tlvlink::trainer {
namespace {

using testing::TempDir;

// See train_export_test.cc for the reasons behind these.
constexpr double kParityCosine = 0.9999;
constexpr double kParityMaxAbsRelative = 1e-4;
// The smoke run is short (48 steps); the last epoch's mean loss must be clearly below the first.
constexpr double kRequiredLossDrop = 0.9;

using ::tlvlink::testing::CliRun;

using ::tlvlink::testing::run_tlvlink;

// Mean student loss per epoch from the JSON-lines log.
std::vector<double> epoch_means(const std::string& log_path) {
  std::ifstream in(log_path);
  std::vector<double> sum, count;
  std::string line;
  while (std::getline(in, line)) {
    const nlohmann::json j = nlohmann::json::parse(line);
    if (j.at("phase") != "student") continue;
    const auto e = j.at("epoch").get<size_t>();
    if (sum.size() <= e) {
      sum.resize(e + 1, 0);
      count.resize(e + 1, 0);
    }
    sum[e] += j.at("loss").get<double>();
    count[e] += 1;
  }
  for (size_t e = 0; e < sum.size(); ++e) sum[e] /= count[e];
  return sum;
}

TEST(TrainerSmoke, GenerateTrainExportParity) {
  const auto t0 = std::chrono::steady_clock::now();
  TempDir dir("smoke");
  const std::string data = dir / "t100k";
  // 24 sessions x 6 frames = 144 samples; 18 sessions (108 frames) train, 6 test.
  ASSERT_RUN(run_tlvlink("sim touch100k -o " + data +
                         " --sessions 24 --frames-per-session 6 --seed 5 --threads 2 "
                         "--vision-height 120 --vision-width 160 --test-fraction 0.25"),
             0);
  const std::string ckpt = dir / "tiny.ckpt";
  const CliRun train_run = run_tlvlink("train " + data + " -o " + ckpt +
                                       " --arch tiny --batch 18 --epochs 8 --lr 2e-3 --warmup 6 "
                                       "--teacher-epochs 3 --seed 1 --threads 1 --checkpoint-dir " +
                                       dir.path() + " --checkpoint-every 24");
  ASSERT_RUN(train_run, 0);
  std::printf("%s", train_run.out.c_str());
  const std::vector<double> means = epoch_means(ckpt + ".log.jsonl");
  ASSERT_EQ(means.size(), 8u);
  std::printf("student mean loss by epoch:");
  for (double m : means) std::printf(" %.4f", m);
  std::printf("\n");
  EXPECT_LT(means.back(), kRequiredLossDrop * means.front());

  const std::string model_path = dir / "tiny.tlvm";
  ASSERT_RUN(run_tlvlink("export " + ckpt + " -o " + model_path), 0);
  auto model = Model::load_file(model_path.c_str());
  ASSERT_TRUE(model.ok()) << model.error().message();
  int64_t n = 0;
  auto frames = testing::preprocessed_frames(data, true, (*model)->metadata().input, 16, n);
  ASSERT_TRUE(frames.ok()) << frames.error().message();
  auto want = libtorch_embeddings(ckpt, *frames, n);
  ASSERT_TRUE(want.ok()) << want.error().message();
  const size_t dim = static_cast<size_t>((*model)->metadata().embedding_dim);
  const size_t per_frame = frames->size() / static_cast<size_t>(n);
  for (ExecutorKind kind : {ExecutorKind::kXnnpack, ExecutorKind::kReference}) {
    auto exec = make_executor(**model, kind);
    ASSERT_TRUE(exec.ok());
    std::vector<float> got;
    for (int64_t i = 0; i < n; ++i) {
      std::memcpy((*exec)->input(0).data(), frames->data() + static_cast<size_t>(i) * per_frame,
                  per_frame * sizeof(float));
      ASSERT_TRUE((*exec)->invoke().ok());
      const auto* f = reinterpret_cast<const float*>((*exec)->output(0).data());
      got.insert(got.end(), f, f + dim);
    }
    const testing::Agreement g = testing::compare_rows(*want, got, n);
    std::printf("smoke parity %s: min cosine %.9f, max-abs %.3g (max |e| %.3g), %lld frames\n",
                executor_kind_name(kind), g.min_cosine, g.max_abs, g.max_magnitude,
                static_cast<long long>(n));
    EXPECT_GE(g.min_cosine, kParityCosine);
    EXPECT_LE(g.max_abs, kParityMaxAbsRelative * std::max(1.0, g.max_magnitude));
  }
  // The exported model runs through the CLI too, and its golden pairs (libtorch outputs on
  // test-split frames) replay on both executors.
  ASSERT_RUN(run_tlvlink("inspect " + model_path), 0);
  EXPECT_EQ((*model)->metadata().golden.size(), 2u);
  ASSERT_RUN(run_tlvlink("verify " + model_path + " --executor xnnpack"), 0);
  ASSERT_RUN(run_tlvlink("verify " + model_path + " --executor reference"), 0);
  std::printf("smoke wall time %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

TEST(TrainerSmoke, BadArgumentsAndFiles) {
  TempDir dir("smoke_bad");
  // Usage errors: exit 2.
  ASSERT_RUN(run_tlvlink("train " + dir.path() + " -o " + (dir / "x.ckpt") + " --batch 1"), 2);
  ASSERT_RUN(run_tlvlink("train " + dir.path() + " -o " + (dir / "x.ckpt") + " --arch huge"), 2);
  ASSERT_RUN(
      run_tlvlink("train " + dir.path() + " -o " + (dir / "x.ckpt") + " --beta-schedule sigmoid"),
      2);
  ASSERT_RUN(run_tlvlink("train " + dir.path()), 2);  // no -o
  CliRun r = run_tlvlink("train " + dir.path() + " -o " + (dir / "x.ckpt") + " --resume " +
                         (dir / "x.ckpt") + " --lr 1e-3");
  ASSERT_RUN(r, 2);
  EXPECT_NE(r.out.find("cannot be combined with --resume"), std::string::npos) << r.out;
  // A directory that is not a dataset: the datasets' one error for it (exit 1, as in eval and
  // quantize), naming the missing index.
  r = run_tlvlink("train " + dir.path() + " -o " + (dir / "x.ckpt"));
  ASSERT_RUN(r, 1);
  EXPECT_NE(r.out.find("data_list.json"), std::string::npos) << r.out;
  // A corrupt checkpoint: a failure of the work (exit 1) naming the file.
  std::ofstream(dir / "junk.ckpt") << "junk";
  r = run_tlvlink("export " + (dir / "junk.ckpt") + " -o " + (dir / "junk.tlvm"));
  ASSERT_RUN(r, 1);
  EXPECT_NE(r.out.find("junk.ckpt"), std::string::npos) << r.out;
  ASSERT_RUN(run_tlvlink("export " + (dir / "missing.ckpt") + " -o " + (dir / "m.tlvm")), 1);
  ASSERT_RUN(run_tlvlink("train --list-archs"), 0);
}

}  // namespace
}  // namespace tlvlink::trainer
