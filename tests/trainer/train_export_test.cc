// Training end to end in-process on a small simulator set: determinism with a seed, resume ==
// uninterrupted, export parity (libtorch eval vs the runtime's fp32 executors, embeddings and
// zero-shot logits), and clear errors for bad inputs.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

#include "data_cache.h"
#include "tlvlink/executor.h"
#include "tlvlink/io/npy.h"
#include "tlvlink/io/sensor_frame.h"
#include "tlvlink/model.h"
#include "tlvlink/text/text_encoder.h"
#include "trainer/trainer_support.h"

namespace tlvlink::trainer {
namespace {

using testing::quick_options;
using testing::TempDir;
using testing::write_touch_set;

// The runtime's fp32 graph vs libtorch eval mode: the same float math in a different order
// (oneDNN vs XNNPACK / reference GEMM blocking) -> relative differences of a few ulps per
// layer; 1e-4 relative to the embedding's scale leaves room for ~15 layers of accumulation.
constexpr double kParityCosine = 0.9999;
constexpr double kParityMaxAbsRelative = 1e-4;
// Zero-shot logits are 100 x cosine, so an embedding cosine of 1 - 1e-8 moves them by ~1e-4.
constexpr double kLogitTolerance = 1e-3;

class Trainer : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>("set");
    // 8 sessions x 6 frames; a quarter of the sessions held out -> 36 train, 12 test.
    const Status s = write_touch_set(data(), 8, 6, 21);
    ASSERT_TRUE(s.ok()) << s.error().message();
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static std::string data() { return *dir_ / "t100k"; }

  static std::unique_ptr<TempDir> dir_;
};
std::unique_ptr<TempDir> Trainer::dir_;

// logit_scale x cosine(embedding, prompt row), as the runtime's zero-shot head computes it.
std::vector<double> zero_shot_logits(const ZeroShotHead& h, std::span<const float> e) {
  const size_t dim = e.size();
  double norm = 0;
  for (float v : e) norm += static_cast<double>(v) * static_cast<double>(v);
  std::vector<double> logits(h.class_names.size());
  for (size_t k = 0; k < logits.size(); ++k) {
    double dot = 0;
    for (size_t i = 0; i < dim; ++i) {
      dot += static_cast<double>(h.prompt_matrix[k * dim + i]) * static_cast<double>(e[i]);
    }
    logits[k] = static_cast<double>(h.logit_scale) * dot / std::sqrt(norm);
  }
  return logits;
}

size_t argmax(const std::vector<double>& v) {
  return static_cast<size_t>(std::max_element(v.begin(), v.end()) - v.begin());
}

std::vector<float> embed(const std::string& ckpt, const std::vector<float>& frames, int64_t n) {
  auto e = libtorch_embeddings(ckpt, frames, n);
  EXPECT_TRUE(e.ok()) << (e.ok() ? "" : e.error().message());
  return e.ok() ? std::move(e).value() : std::vector<float>{};
}

// A run resumed from `checkpoint` in `out` with the settings it recorded, into resumed.ckpt.
Result<TrainSummary> resume(const std::string& data_dir, const TempDir& out,
                            const char* checkpoint) {
  TrainOptions o;
  o.data_dir = data_dir;
  o.output = out / "resumed.ckpt";
  o.resume = out / checkpoint;
  return train(o);
}

TEST_F(Trainer, SameSeedSameModel) {
  TempDir out("seed");
  int64_t n = 0;
  TrainOptions a = quick_options(data(), out / "a.ckpt");
  TrainOptions b = quick_options(data(), out / "b.ckpt");
  auto ra = train(a), rb = train(b);
  ASSERT_TRUE(ra.ok()) << ra.error().message();
  ASSERT_TRUE(rb.ok()) << rb.error().message();
  EXPECT_EQ(ra->train_samples, 36);
  EXPECT_EQ(ra->final_loss, rb->final_loss);
  auto info = read_checkpoint_info(out / "a.ckpt");
  ASSERT_TRUE(info.ok());
  auto frames = testing::preprocessed_frames(data(), true, info->input, 4, n);
  ASSERT_TRUE(frames.ok());
  EXPECT_EQ(embed(out / "a.ckpt", *frames, n), embed(out / "b.ckpt", *frames, n));
  // A different seed gives a different model.
  TrainOptions c = quick_options(data(), out / "c.ckpt");
  c.seed = 4;
  ASSERT_TRUE(train(c).ok());
  EXPECT_NE(embed(out / "a.ckpt", *frames, n), embed(out / "c.ckpt", *frames, n));
}

TEST_F(Trainer, ResumeEqualsUninterrupted) {
  TempDir out("resume");
  TrainOptions whole = quick_options(data(), out / "whole.ckpt");
  whole.epochs = 3;  // 4 steps per epoch -> 12 steps
  whole.checkpoint_dir = out.path();
  whole.checkpoint_every = 5;
  auto rw = train(whole);
  ASSERT_TRUE(rw.ok()) << rw.error().message();
  ASSERT_TRUE(std::filesystem::exists(out / "step_0000005.ckpt"));
  ASSERT_TRUE(std::filesystem::exists(out / "step_0000012.ckpt"));

  TrainOptions resumed;
  resumed.data_dir = data();
  resumed.output = out / "resumed.ckpt";
  resumed.resume = out / "step_0000005.ckpt";
  resumed.threads = whole.threads;
  auto rr = train(resumed);
  ASSERT_TRUE(rr.ok()) << rr.error().message();
  EXPECT_EQ(rr->start_step, 5);
  EXPECT_EQ(rr->steps, 12);
  EXPECT_EQ(rr->final_loss, rw->final_loss);
  EXPECT_EQ(rr->last_epoch_loss, rw->last_epoch_loss);

  auto info = read_checkpoint_info(out / "whole.ckpt");
  ASSERT_TRUE(info.ok());
  int64_t n = 0;
  auto frames = testing::preprocessed_frames(data(), true, info->input, 4, n);
  ASSERT_TRUE(frames.ok());
  EXPECT_EQ(embed(out / "whole.ckpt", *frames, n), embed(out / "resumed.ckpt", *frames, n));
}

TEST_F(Trainer, SupervisedObjectiveLearnsTheLabelsAndExportsNoZeroShotHeads) {
  // The supervised upper bound: cross-entropy on the sidecar's labels, no text, no teacher.
  TempDir out("sup");
  TrainOptions o = quick_options(data(), out / "s.ckpt");
  o.objective = Objective::kSupervised;
  o.beta.schedule = BetaSchedule::kNone;
  o.epochs = 6;
  auto r = train(o);
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_EQ(r->teacher_seconds, 0.0);
  // Three cross-entropies start near ln 20 + 2 ln 2 = 4.38 and must fall on 36 samples.
  EXPECT_GT(r->first_epoch_loss, 3.0);
  EXPECT_LT(r->last_epoch_loss, r->first_epoch_loss - 0.3);
  ExportOptions eo;
  eo.checkpoint = out / "s.ckpt";
  eo.output = out / "s.tlvm";
  auto e = export_model(eo);
  ASSERT_TRUE(e.ok()) << e.error().message();
  EXPECT_TRUE(e->zero_shot_heads.empty());
  EXPECT_NE(e->note.find("objective supervised"), std::string::npos) << e->note;
  auto m = Model::load_file((out / "s.tlvm").c_str());
  ASSERT_TRUE(m.ok()) << m.error().message();
  EXPECT_TRUE((*m)->metadata().zero_shot_heads.empty());
  EXPECT_NE((*m)->metadata().provenance.training.find("\"kind\":\"supervised\""),
            std::string_view::npos);
  // With a curriculum the objective is refused (no text loss for it to act on).
  o.beta.schedule = BetaSchedule::kLinear;
  EXPECT_EQ(train(o).error().code(), ErrorCode::kInvalidArgument);
}

TEST_F(Trainer, MultiTaskWithAugmentationIsReproducibleAndResumes) {
  // InfoNCE + cross-entropy with sensor augmentation: the augmentation is drawn from (seed,
  // step, sample), so two runs agree bit for bit and a resumed run equals an uninterrupted one.
  TempDir out("multi");
  auto options = [&](const std::string& name) {
    TrainOptions o = quick_options(data(), out / name);
    o.objective = Objective::kTlvLinkSupervised;
    o.supervised_weight = 0.5;
    o.augment = {0.05, 0.05, 2.0};
    o.epochs = 3;
    return o;
  };
  TrainOptions whole = options("whole.ckpt");
  whole.checkpoint_dir = out.path();
  whole.checkpoint_every = 5;
  auto rw = train(whole);
  ASSERT_TRUE(rw.ok()) << rw.error().message();
  auto again = train(options("again.ckpt"));
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->final_loss, rw->final_loss);
  auto rr = resume(data(), out, "step_0000005.ckpt");
  ASSERT_TRUE(rr.ok()) << rr.error().message();
  EXPECT_EQ(rr->final_loss, rw->final_loss);
  // Without augmentation the run differs (the augmentation did something).
  TrainOptions plain = options("plain.ckpt");
  plain.augment = {};
  auto rp = train(plain);
  ASSERT_TRUE(rp.ok());
  EXPECT_NE(rp->final_loss, rw->final_loss);
}

TEST_F(Trainer, SensorViewsWithConsistencyAreReproducibleResumeAndExportTheirResize) {
  // Two views per sample made on a worker thread, the consistency terms and the area resize:
  // views are drawn from (seed, step, sample, view), so runs agree bit for bit, a resumed run
  // equals an uninterrupted one, and the exported model records the filter it was trained with.
  TempDir out("views");
  auto options = [&](const std::string& name) {
    TrainOptions o = quick_options(data(), out / name);
    o.objective = Objective::kTlvLinkSupervised;
    o.resize = ResizeFilter::kArea;
    o.view.components = kViewAll;
    o.view.consistency_weight = 2;
    o.view.prediction_weight = 1;
    o.epochs = 3;
    return o;
  };
  TrainOptions whole = options("whole.ckpt");
  whole.checkpoint_dir = out.path();
  whole.checkpoint_every = 5;
  auto rw = train(whole);
  ASSERT_TRUE(rw.ok()) << rw.error().message();
  auto again = train(options("again.ckpt"));
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->final_loss, rw->final_loss);
  auto rr = resume(data(), out, "step_0000005.ckpt");
  ASSERT_TRUE(rr.ok()) << rr.error().message();
  EXPECT_EQ(rr->final_loss, rw->final_loss);
  TrainOptions one_view = options("one.ckpt");
  one_view.view.consistency_weight = 0;
  one_view.view.prediction_weight = 0;
  auto r1 = train(one_view);
  ASSERT_TRUE(r1.ok());
  EXPECT_NE(r1->final_loss, rw->final_loss);
  // Codec twins as half of the pairs: another run, and as reproducible.
  TrainOptions twins = options("twins.ckpt");
  twins.view.codec_pairs = 0.5;
  auto rt = train(twins);
  ASSERT_TRUE(rt.ok()) << rt.error().message();
  EXPECT_NE(rt->final_loss, rw->final_loss);
  twins.output = out / "twins-again.ckpt";
  auto rt2 = train(twins);
  ASSERT_TRUE(rt2.ok());
  EXPECT_EQ(rt2->final_loss, rt->final_loss);
  ExportOptions e;
  e.checkpoint = out / "whole.ckpt";
  e.output = out / "whole.tlvm";
  ASSERT_TRUE(export_model(e).ok());
  auto model = Model::load_file(e.output.c_str());
  ASSERT_TRUE(model.ok());
  EXPECT_EQ((*model)->metadata().input.resize_filter, ResizeFilter::kArea);
  // The model records the camera views it learnt, and a frame of another sensor is refused.
  EXPECT_EQ(tools::trained_sensors(**model), std::vector<std::string>{"gelsight-mini"});
  tools::SensorFrame digit;
  digit.sensor = "digit";
  const Status refused = tools::check_trained_sensor(**model, digit, "d.png");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(std::string(refused.error().message()).find("trained on gelsight-mini frames only"),
            std::string::npos);
  digit.sensor = "gelsight-mini";
  EXPECT_TRUE(tools::check_trained_sensor(**model, digit, "m.png").ok());
}

TEST_F(Trainer, ContactRegressionReadsTheSidecarTrainsAndResumes) {
  // The cache carries each frame's ln(force) and friction from the sidecar (the targets).
  CacheOptions co;
  co.dir = data();
  co.load_vision = false;
  auto cache = load_cache(co);
  ASSERT_TRUE(cache.ok()) << cache.error().message();
  ASSERT_EQ(cache->log_force.size(), cache->keys.size());
  ASSERT_EQ(cache->friction.size(), cache->keys.size());
  int64_t with_targets = 0;
  for (size_t i = 0; i < cache->keys.size(); ++i) {
    if (!std::isfinite(cache->log_force[i])) continue;
    ++with_targets;
    // Simulated presses: 1-15 N, friction 0.15-1.2 (tools/sim/src/gen: touch_generator.cc,
    // materials.cc), with a margin.
    EXPECT_GT(cache->log_force[i], std::log(0.5f)) << cache->keys[i];
    EXPECT_LT(cache->log_force[i], std::log(40.0f)) << cache->keys[i];
    EXPECT_GT(cache->friction[i], 0.1f) << cache->keys[i];
    EXPECT_LT(cache->friction[i], 1.5f) << cache->keys[i];
  }
  EXPECT_GT(with_targets, 0);

  // The term is in the loss (a squared error of O(1) added to the first epoch), it is off at
  // weight 0, and a run that uses it resumes exactly (the checkpoint keeps its layer).
  TempDir out("contact");
  auto options = [&](const std::string& name, double contact) {
    TrainOptions o = quick_options(data(), out / name);
    o.objective = Objective::kSupervised;
    o.beta.schedule = BetaSchedule::kNone;
    o.contact_weight = contact;
    o.epochs = 3;
    return o;
  };
  TrainOptions whole = options("whole.ckpt", 1.0);
  whole.checkpoint_dir = out.path();
  whole.checkpoint_every = 5;
  auto with = train(whole);
  auto without = train(options("off.ckpt", 0.0));
  ASSERT_TRUE(with.ok()) << with.error().message();
  ASSERT_TRUE(without.ok()) << without.error().message();
  EXPECT_GT(with->first_epoch_loss, without->first_epoch_loss);
  EXPECT_LT(with->last_epoch_loss, with->first_epoch_loss);
  auto rr = resume(data(), out, "step_0000005.ckpt");
  ASSERT_TRUE(rr.ok()) << rr.error().message();
  EXPECT_EQ(rr->final_loss, with->final_loss);
  // A weight outside [0, 100] is refused before any work.
  TrainOptions bad = options("bad.ckpt", -1.0);
  auto rb = train(bad);
  ASSERT_FALSE(rb.ok());
  EXPECT_EQ(rb.error().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(std::string(rb.error().message()).find("contact weight"), std::string::npos)
      << rb.error().message();
}

TEST_F(Trainer, ExportedModelMatchesLibtorch) {
  TempDir out("parity");
  TrainOptions o = quick_options(data(), out / "m.ckpt");
  o.beta.schedule = BetaSchedule::kCosine;
  ASSERT_TRUE(train(o).ok());
  ExportOptions e;
  e.checkpoint = out / "m.ckpt";
  e.output = out / "m.tlvm";
  auto exported = export_model(e);
  ASSERT_TRUE(exported.ok()) << exported.error().message();
  EXPECT_EQ(exported->zero_shot_heads.size(), 4u);

  auto model = Model::load_file(e.output.c_str());
  ASSERT_TRUE(model.ok()) << model.error().message();
  const Metadata& meta = (*model)->metadata();
  EXPECT_EQ(meta.input.height, 48);
  EXPECT_EQ(meta.input.width, 64);
  EXPECT_EQ(meta.embedding_dim, 128);
  ASSERT_EQ(meta.zero_shot_heads.size(), 4u);
  EXPECT_EQ(meta.zero_shot_heads[0].class_names.size(), 20u);
  EXPECT_EQ(meta.zero_shot_heads[0].logit_scale, 100.0f);
  EXPECT_TRUE(meta.linear_heads.empty());
  EXPECT_EQ(meta.golden.size(), 2u);  // from the recorded training set's test split
  EXPECT_EQ(exported->golden_pairs, 2);
  EXPECT_NE(meta.provenance.training.find("hashing-v1"), std::string_view::npos);

  // Held-out frames through the runtime's preprocessing (tools::preprocess with the model's
  // own InputSpec), then libtorch eval vs both fp32 executors.
  int64_t n = 0;
  auto frames = testing::preprocessed_frames(data(), true, meta.input, 12, n);
  ASSERT_TRUE(frames.ok());
  const std::vector<float> want = embed(e.checkpoint, *frames, n);
  ASSERT_EQ(want.size(), static_cast<size_t>(n) * 128);
  const size_t per_frame = frames->size() / static_cast<size_t>(n);
  for (ExecutorKind kind : {ExecutorKind::kReference, ExecutorKind::kXnnpack}) {
    auto exec = make_executor(**model, kind);
    ASSERT_TRUE(exec.ok()) << exec.error().message();
    std::vector<float> got;
    for (int64_t i = 0; i < n; ++i) {
      std::memcpy((*exec)->input(0).data(), frames->data() + static_cast<size_t>(i) * per_frame,
                  per_frame * sizeof(float));
      ASSERT_TRUE((*exec)->invoke().ok());
      const auto out_bytes = (*exec)->output(0);
      const auto* f = reinterpret_cast<const float*>(out_bytes.data());
      got.insert(got.end(), f, f + 128);
    }
    const testing::Agreement g = testing::compare_rows(want, got, n);
    std::printf(
        "%s vs libtorch on %lld held-out frames: min cosine %.9f, max-abs %.3g "
        "(max |e| %.3g)\n",
        executor_kind_name(kind), static_cast<long long>(n), g.min_cosine, g.max_abs,
        g.max_magnitude);
    EXPECT_GE(g.min_cosine, kParityCosine);
    EXPECT_LE(g.max_abs, kParityMaxAbsRelative * std::max(1.0, g.max_magnitude));
    // Zero-shot logits through the same head code from either embedding.
    double worst = 0;
    int64_t top1_disagreements = 0;
    for (int64_t i = 0; i < n; ++i) {
      for (const ZeroShotHead& h : meta.zero_shot_heads) {
        const auto a = zero_shot_logits(
            h, std::span<const float>(want).subspan(static_cast<size_t>(i) * 128, 128));
        const auto b = zero_shot_logits(
            h, std::span<const float>(got).subspan(static_cast<size_t>(i) * 128, 128));
        for (size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k] - b[k]));
        top1_disagreements += argmax(a) != argmax(b);
      }
    }
    EXPECT_EQ(top1_disagreements, 0);
    std::printf("  zero-shot logits max |diff| %.3g\n", worst);
    EXPECT_LE(worst, kLogitTolerance);
  }
}

TEST_F(Trainer, NoCurriculumNeedsNoTeacher) {
  TempDir out("nocurr");
  TrainOptions o = quick_options(data(), out / "n.ckpt");
  o.beta.schedule = BetaSchedule::kNone;
  auto r = train(o);
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_EQ(r->teacher_seconds, 0.0);
  auto info = read_checkpoint_info(out / "n.ckpt");
  ASSERT_TRUE(info.ok());
  EXPECT_NE(info->meta_json.find("\"schedule\":\"none\""), std::string::npos);
  // Every logged beta is 0.
  std::ifstream log(out / "n.ckpt.log.jsonl");
  std::string line;
  int lines = 0;
  while (std::getline(log, line)) {
    ++lines;
    EXPECT_NE(line.find("\"beta\":0,"), std::string::npos) << line;
  }
  EXPECT_EQ(lines, 8);  // 2 epochs x 4 steps, no teacher phase
}

TEST_F(Trainer, TorchScriptTeacherWithProjection) {
  TempDir out("jit");
  const std::string cmd =
      std::string("/usr/bin/python3 ") + TLVLINK_MAKE_TEACHER + " " + out.path() + " 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    GTEST_SKIP() << "cannot write TorchScript teachers (" << cmd
                 << "); install python3-torch (tools/setup/install_deps.sh test)";
  }
  TrainOptions o = quick_options(data(), out / "jit.ckpt");
  o.teacher.torchscript = out / "teacher64.pt";
  o.teacher.input_height = 32;
  o.teacher.input_width = 40;
  auto r = train(o);
  ASSERT_TRUE(r.ok()) << r.error().message();
  auto info = read_checkpoint_info(out / "jit.ckpt");
  ASSERT_TRUE(info.ok());
  EXPECT_NE(info->meta_json.find("\"teacher_dim\":64"), std::string::npos);
  EXPECT_NE(info->meta_json.find("torchscript"), std::string::npos);
  // The projection (64 -> 128) survives a resume.
  TrainOptions more;
  more.data_dir = data();
  more.output = out / "more.ckpt";
  more.resume = out / "jit.ckpt";
  more.threads = o.threads;
  auto rr = train(more);
  ASSERT_TRUE(rr.ok()) << rr.error().message();
  // A module that returns the wrong shape is refused with the shape it returned.
  o.teacher.torchscript = out / "bad_shape.pt";
  auto bad = train(o);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(std::string(bad.error().message()).find("returned shape"), std::string::npos)
      << bad.error().message();
  o.teacher.torchscript = out / "missing.pt";
  EXPECT_EQ(train(o).error().code(), ErrorCode::kFormat);
}

// Precomputed embeddings (tools/text/README.md layout) of every sample and prompt: seeded random
// unit vectors of dimension `dim`; `skip_key` leaves one sample out.
void write_precomputed(const std::string& data_dir, const std::string& out, int32_t dim,
                       const std::string& skip_key = "") {
  std::filesystem::create_directories(out);
  std::vector<std::string> keys;
  std::ifstream list(data_dir + "/data_list.json");
  std::string line;
  while (std::getline(list, line)) {
    const size_t a = line.find("\"img\":\"") + 7, b = line.find('"', a);
    const std::string key = line.substr(a, b - a);
    if (key != skip_key) keys.push_back(key);
  }
  std::vector<std::string> prompts;
  for (const text::PromptSet& set : {text::material_prompts(), text::hardness_prompts(),
                                     text::roughness_prompts(), text::grasp_prompts()})
    for (size_t c = 0; c < set.class_names.size(); ++c)
      for (const std::string& p : set.prompts_for(c)) prompts.push_back(p);
  uint64_t state = 99;
  auto rows = [&](size_t n) {
    std::vector<float> v(n * static_cast<size_t>(dim));
    for (float& x : v) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      x = static_cast<float>(static_cast<int64_t>(state >> 40) - (int64_t{1} << 23)) / 8388608.0f;
    }
    return v;
  };
  auto write_lines = [](const std::string& path, const std::vector<std::string>& lines) {
    std::ofstream f(path);
    for (const std::string& l : lines) f << l << "\n";
  };
  const auto n = static_cast<int64_t>(keys.size()), pn = static_cast<int64_t>(prompts.size());
  write_lines(out + "/keys.txt", keys);
  write_lines(out + "/prompts.txt", prompts);
  ASSERT_TRUE(tools::write_npy(out + "/sentence.npy",
                               tools::NpyArray::from<float>({n, dim}, rows(keys.size())))
                  .ok());
  ASSERT_TRUE(tools::write_npy(out + "/phrase.npy",
                               tools::NpyArray::from<float>({n, dim}, rows(keys.size())))
                  .ok());
  ASSERT_TRUE(tools::write_npy(out + "/prompts.npy",
                               tools::NpyArray::from<float>({pn, dim}, rows(prompts.size())))
                  .ok());
}

// A user's own frozen text model: training aligns the student with the precomputed sentence +
// phrase embeddings (the embedding takes their dimension), export builds every zero-shot matrix
// from the precomputed prompt embeddings, and a sample without an embedding is an error naming it.
TEST_F(Trainer, PrecomputedTextEmbeddingsTrainAndExport) {
  TempDir out("precomputed");
  constexpr int32_t kDim = 32;
  write_precomputed(data(), out / "emb", kDim);
  TrainOptions o = quick_options(data(), out / "p.ckpt");
  o.text.embeddings_dir = out / "emb";
  auto r = train(o);
  ASSERT_TRUE(r.ok()) << r.error().message();
  ExportOptions e;
  e.checkpoint = out / "p.ckpt";
  e.output = out / "p.tlvm";
  auto exported = export_model(e);
  ASSERT_TRUE(exported.ok()) << exported.error().message();
  auto model = Model::load_file(e.output.c_str());
  ASSERT_TRUE(model.ok()) << model.error().message();
  const Metadata& meta = (*model)->metadata();
  EXPECT_EQ(meta.embedding_dim, kDim);
  EXPECT_NE(meta.provenance.training.find("precomputed"), std::string::npos);
  auto enc = text::open_precomputed_text_embeddings(out / "emb");
  ASSERT_TRUE(enc.ok()) << enc.error().message();
  const text::PromptSet sets[] = {text::material_prompts(), text::hardness_prompts(),
                                  text::roughness_prompts(), text::grasp_prompts()};
  ASSERT_EQ(meta.zero_shot_heads.size(), 4u);
  for (size_t h = 0; h < 4; ++h) {
    SCOPED_TRACE(sets[h].task);
    auto want = text::zero_shot_matrix(**enc, sets[h]);
    ASSERT_TRUE(want.ok()) << want.error().message();
    const auto& got = meta.zero_shot_heads[h].prompt_matrix;
    ASSERT_EQ(got.size(), want->size());
    for (size_t i = 0; i < got.size(); ++i) EXPECT_FLOAT_EQ(got[i], (*want)[i]) << i;
  }

  // One training sample without its embedding: the error names the key.
  std::string first_key;
  {
    std::ifstream list(data() + "/data_list.json");
    std::string line;
    std::getline(list, line);
    const size_t a = line.find("\"img\":\"") + 7;
    first_key = line.substr(a, line.find('"', a) - a);
  }
  write_precomputed(data(), out / "partial", kDim, first_key);
  TrainOptions partial = quick_options(data(), out / "q.ckpt");
  partial.text.embeddings_dir = out / "partial";
  auto bad = train(partial);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(std::string(bad.error().message()).find(first_key), std::string::npos)
      << bad.error().message();
}

// The error of a run that must fail (an "ok" error when it unexpectedly succeeds).
Error train_error(const TrainOptions& o) {
  auto r = train(o);
  EXPECT_FALSE(r.ok()) << "training " << o.data_dir << " succeeded";
  return r.ok() ? Error() : r.error();
}

bool mentions(const Error& e, const char* text) {
  return std::string(e.message()).find(text) != std::string::npos;
}

TEST_F(Trainer, BadInputsGiveClearErrors) {
  TempDir out("bad");
  // An empty directory.
  std::filesystem::create_directories(out / "empty");
  Error e = train_error(quick_options(out / "empty", out / "x.ckpt"));
  EXPECT_EQ(e.code(), ErrorCode::kFormat);  // not a dataset: the datasets' one code for it
  EXPECT_TRUE(mentions(e, "data_list.json")) << e.message();
  // An index with no samples.
  std::filesystem::create_directories(out / "blank");
  std::ofstream(out / "blank/data_list.json") << "\n";
  e = train_error(quick_options(out / "blank", out / "x.ckpt"));
  EXPECT_TRUE(mentions(e, "no train samples")) << e.message();
  // A batch larger than the training split.
  TrainOptions big = quick_options(data(), out / "x.ckpt");
  big.batch = 64;
  e = train_error(big);
  EXPECT_TRUE(mentions(e, "fewer than one batch")) << e.message();
  // An image cache limit below what the set needs.
  TrainOptions small_cache = quick_options(data(), out / "x.ckpt");
  small_cache.max_cache_bytes = 1000;
  EXPECT_EQ(train_error(small_cache).code(), ErrorCode::kOutOfMemory);
  // Corrupt checkpoints: random bytes, and a real one cut in half.
  std::ofstream(out / "junk.ckpt") << "this is not a checkpoint";
  auto info = read_checkpoint_info(out / "junk.ckpt");
  ASSERT_FALSE(info.ok());
  EXPECT_EQ(info.error().code(), ErrorCode::kFormat);
  ASSERT_TRUE(train(quick_options(data(), out / "good.ckpt")).ok());
  const auto size = std::filesystem::file_size(out / "good.ckpt");
  std::filesystem::copy_file(out / "good.ckpt", out / "cut.ckpt");
  std::filesystem::resize_file(out / "cut.ckpt", size / 2);
  ExportOptions ex;
  ex.checkpoint = out / "cut.ckpt";
  ex.output = out / "cut.tlvm";
  auto exported = export_model(ex);
  ASSERT_FALSE(exported.ok());
  EXPECT_EQ(exported.error().code(), ErrorCode::kFormat);
  std::printf("truncated checkpoint: %s\n", exported.error().message());
  TrainOptions resume_junk;
  resume_junk.data_dir = data();
  resume_junk.output = out / "y.ckpt";
  resume_junk.resume = out / "junk.ckpt";
  EXPECT_EQ(train_error(resume_junk).code(), ErrorCode::kFormat);
  // Resuming on a different set is refused.
  TempDir other("other");
  ASSERT_TRUE(write_touch_set(other / "t100k", 8, 6, 99).ok());
  TrainOptions elsewhere;
  elsewhere.data_dir = other / "t100k";
  elsewhere.output = out / "z.ckpt";
  elsewhere.resume = out / "good.ckpt";
  e = train_error(elsewhere);
  EXPECT_TRUE(mentions(e, "differ")) << e.message();
}

}  // namespace
}  // namespace tlvlink::trainer
