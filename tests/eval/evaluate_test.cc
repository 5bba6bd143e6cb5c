// evaluate_embeddings on hand-made embeddings: zero-shot with a hand-made prompt matrix (cosine,
// scale, labels matched by name), the grasp zero-shot average over A/B x before/after, the
// model's stored heads, the table's structure, task conventions.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/heads/grasp_layout.h"
#include "tlvlink/heads/head_math.h"

#include "tlvlink/eval/eval.h"

namespace tlvlink {
namespace {

using eval::Method;
using eval::Task;

constexpr int32_t kDim = 4;
// Zero-shot logits are 100 * cosine in float: a few float roundings of values <= 100.
constexpr float kLogitTolerance = 1e-4f;

std::vector<float> unit(float a, float b, float c, float d) {
  const float n = std::sqrt(a * a + b * b + c * c + d * d);
  return {a / n, b / n, c / n, d / n};
}

// Touch rows: hard samples near axis 0, soft near axis 1; sessions h<i> / s<i>.
eval::TouchEmbeddings touch_set() {
  eval::TouchEmbeddings t;
  t.dim = kDim;
  for (int i = 0; i < 12; ++i) {
    const bool hard = i % 2 == 0;
    const float jitter = 0.05f * static_cast<float>(i);
    const std::vector<float> e = hard ? std::vector<float>{2.0f, jitter, 0.3f, 0.1f}
                                      : std::vector<float>{jitter, 3.0f, 0.1f, 0.3f};
    t.values.insert(t.values.end(), e.begin(), e.end());
    t.hard.push_back(hard ? 1 : 0);
    t.material.push_back(-1);
    t.rough.push_back(i == 11 ? -1 : (hard ? 1 : 0));  // one test sample without a rough label
    t.group.push_back((hard ? "h" : "s") + std::to_string(i / 2));
    t.is_test.push_back(i >= 8 ? 1 : 0);
    t.keys.push_back("k" + std::to_string(i));
  }
  return t;
}

// Grasp episodes whose before/after frames lean to the label but whose A.before frame alone
// points the other way, and whose during frames all point the other way: only the average over
// A/B x before/after gets every episode right.
eval::GraspEmbeddings grasp_set() {
  eval::GraspEmbeddings g;
  g.dim = kDim;
  const std::vector<float> falling = unit(0, 0, 1, 0), lifted = unit(0, 0, 0, 1);
  for (int i = 0; i < 8; ++i) {
    const bool label = i % 2 == 1;
    const std::vector<float>& wrong = label ? falling : lifted;
    const std::vector<float> lean = label ? unit(0, 0, 0.3f, 0.954f) : unit(0, 0, 0.954f, 0.3f);
    for (int f = 0; f < 2; ++f) {
      for (int m = 0; m < 3; ++m) {
        const std::vector<float>* e = &lean;
        if (m == 1) e = &wrong;            // during: never used by the zero-shot test
        if (f == 0 && m == 0) e = &wrong;  // A.before: wrong on its own
        g.values.insert(g.values.end(), e->begin(), e->end());
      }
    }
    g.label.push_back(label ? 1 : 0);
    g.group.push_back("obj" + std::to_string(i));
    g.is_test.push_back(i >= 4 ? 1 : 0);
    g.keys.push_back("e" + std::to_string(i));
  }
  return g;
}

struct Heads {
  // Zero-shot "hard" head with classes in the reverse of the canonical order: matched by name.
  std::vector<float> hard_prompts = [] {
    std::vector<float> m = unit(1, 0, 0, 0);
    const std::vector<float> soft = unit(0, 1, 0, 0);
    m.insert(m.end(), soft.begin(), soft.end());
    return m;
  }();
  std::vector<float> grasp_prompts = [] {
    std::vector<float> m = unit(0, 0, 1, 0);
    const std::vector<float> lifted = unit(0, 0, 0, 1);
    m.insert(m.end(), lifted.begin(), lifted.end());
    return m;
  }();
  std::vector<float> linear_w = {1, 0, 0, 0, 0, 1, 0, 0};  // rows: "hard", "soft"
  std::vector<float> linear_b = {0, 0};
  Metadata metadata() const {
    Metadata m;
    m.name = "hand-made";
    m.embedding_dim = kDim;
    m.zero_shot_heads.push_back({"hard", {"hard", "soft"}, "t", hard_prompts, 100.0f});
    m.zero_shot_heads.push_back({"grasp", {"falling", "lifted"}, "t", grasp_prompts, 100.0f});
    m.linear_heads.push_back({"hard_soft", {"hard", "soft"}, linear_w, linear_b});
    return m;
  }
};

eval::EvalOptions model_only_options() {
  eval::EvalOptions o;
  o.zero_shot = eval::ZeroShotSource::kModel;
  o.oracle_samples = 0;
  return o;
}

TEST(ZeroShot, LogitsAreScaledCosine) {
  Heads h;
  const std::vector<float> e = {3, 4, 0, 0};  // |e| = 5
  std::vector<float> logits(2);
  heads::zero_shot_logits(h.hard_prompts, 100.0f, e, logits);
  EXPECT_NEAR(logits[0], 60.0f, kLogitTolerance);
  EXPECT_NEAR(logits[1], 80.0f, kLogitTolerance);
}

TEST(Evaluate, HandMadePromptMatrixAndStoredHeads) {
  Heads h;
  const Metadata m = h.metadata();
  eval::EmbeddingSet set;
  set.touch = touch_set();
  set.grasp = grasp_set();
  // The hand-made grasp set has embeddings only (no difference features): its probe reads them.
  eval::EvalOptions o = model_only_options();
  o.heads.grasp_features = eval::GraspFeatures::kBeforeDuring;
  auto r = eval::evaluate_embeddings(m, set, o);
  ASSERT_TRUE(r.ok()) << r.error().message();
  ASSERT_EQ(r->results.size(), 12u);  // 3 methods x 4 tasks
  // The default features need the difference statistics, and say so.
  const auto missing = eval::evaluate_embeddings(m, set, model_only_options());
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(std::string(missing.error().message()).find("--grasp-features before-during"),
            std::string::npos)
      << missing.error().message();
  for (size_t i = 0; i < r->results.size(); ++i) {
    EXPECT_EQ(r->results[i].method, static_cast<Method>(i / 4));
    EXPECT_EQ(r->results[i].task, eval::kAllTasks[i % 4]);
  }
  const eval::TaskResult* zs_hard = r->find(Task::kHard, Method::kZeroShot);
  ASSERT_TRUE(zs_hard && zs_hard->available) << (zs_hard ? zs_hard->note : "");
  EXPECT_EQ(zs_hard->n, 4);
  EXPECT_EQ(zs_hard->correct, 4);
  EXPECT_EQ(zs_hard->chance, 0.5);
  EXPECT_EQ(zs_hard->majority, 0.5);
  const eval::TaskResult* zs_grasp = r->find(Task::kGrasp, Method::kZeroShot);
  ASSERT_TRUE(zs_grasp && zs_grasp->available) << (zs_grasp ? zs_grasp->note : "");
  EXPECT_EQ(zs_grasp->n, 4);
  EXPECT_EQ(zs_grasp->correct, 4);  // the average over A/B x before/after, not A.before alone
  // No material / rough zero-shot head and --zero-shot model: unavailable, with the reason.
  const eval::TaskResult* zs_mat = r->find(Task::kMaterial, Method::kZeroShot);
  EXPECT_FALSE(zs_mat->available);
  EXPECT_NE(zs_mat->note.find("no material zero-shot head"), std::string::npos) << zs_mat->note;
  // The model's linear head, labels in its own order.
  const eval::TaskResult* mh = r->find(Task::kHard, Method::kModelHeads);
  ASSERT_TRUE(mh->available) << mh->note;
  EXPECT_EQ(mh->correct, 4);
  EXPECT_FALSE(r->find(Task::kGrasp, Method::kModelHeads)->available);
  // Probes: hard and rough fitted (separable), material has no labels.
  EXPECT_EQ(r->find(Task::kHard, Method::kProbe)->correct, 4);
  const eval::TaskResult* rough = r->find(Task::kRough, Method::kProbe);
  EXPECT_EQ(rough->n, 3);
  EXPECT_EQ(rough->unlabelled, 1);
  EXPECT_FALSE(r->find(Task::kMaterial, Method::kProbe)->available);
  EXPECT_NE(r->find(Task::kMaterial, Method::kProbe)->note.find("no labelled training rows"),
            std::string::npos);
  EXPECT_EQ(r->find(Task::kGrasp, Method::kProbe)->n, 4);
  // The table names every row and the paper's reference.
  const eval::EvalReport* reports[] = {&*r};
  const std::string table = eval::format_table(reports);
  for (const char* s : {"linear probe", "model's heads", "zero-shot", "chance", "Material",
                        "Hard/Soft", "Rough/Smooth", "Grasp", "paper (real data)", "67.2"}) {
    EXPECT_NE(table.find(s), std::string::npos) << s << "\n" << table;
  }
  EXPECT_NE(eval::report_json(reports).find("\"zero-shot\""), std::string::npos);
}

eval::TaskResult scored(Task task, std::vector<uint8_t> item_correct) {
  eval::TaskResult r;
  r.task = task;
  r.method = Method::kModelHeads;
  r.available = true;
  r.n = static_cast<int64_t>(item_correct.size());
  r.item_correct = std::move(item_correct);
  return r;
}

TEST(Evaluate, DiscordanceCountsEachSideAndTestsThemExactly) {
  // 13 disagreements, 10 vs 3: two-sided exact p = 2 (C(13,0)+C(13,1)+C(13,2)+C(13,3)) / 2^13
  // = 2 * 378 / 8192, computed in closed form here; the function sums lgamma terms (1e-12).
  std::vector<uint8_t> a(40, 1), b(40, 1);
  for (int i = 0; i < 10; ++i) b[static_cast<size_t>(i)] = 0;   // only a right
  for (int i = 10; i < 13; ++i) a[static_cast<size_t>(i)] = 0;  // only b right
  a[20] = b[20] = 0;                                            // both wrong: not counted
  auto d = eval::discordance(scored(Task::kGrasp, a), scored(Task::kGrasp, b));
  ASSERT_TRUE(d.ok()) << d.error().message();
  EXPECT_EQ(d->only_first, 10);
  EXPECT_EQ(d->only_second, 3);
  EXPECT_NEAR(d->p, 2.0 * 378.0 / 8192.0, 1e-12);
  // One-sided 0 vs 5: 2 / 32. No disagreement: 1.
  std::vector<uint8_t> c(5, 0), e(5, 1);
  EXPECT_NEAR(eval::discordance(scored(Task::kGrasp, c), scored(Task::kGrasp, e))->p, 0.0625,
              1e-12);
  EXPECT_EQ(eval::discordance(scored(Task::kGrasp, a), scored(Task::kGrasp, a))->p, 1.0);
  // Large n stays finite (no underflowing term): 5,000 vs 5,000 gives p 1.
  std::vector<uint8_t> f(10000, 0), g(10000, 0);
  for (size_t i = 0; i < 5000; ++i) f[i] = 1;
  for (size_t i = 5000; i < 10000; ++i) g[i] = 1;
  const auto big = eval::discordance(scored(Task::kGrasp, f), scored(Task::kGrasp, g));
  ASSERT_TRUE(big.ok());
  EXPECT_NEAR(big->p, 1.0, 1e-9);
  // Different items or tasks: an error naming the task.
  const auto sizes = eval::discordance(scored(Task::kGrasp, a), scored(Task::kGrasp, c));
  ASSERT_FALSE(sizes.ok());
  EXPECT_NE(std::string(sizes.error().message()).find("different test items"), std::string::npos)
      << sizes.error().message();
  EXPECT_FALSE(eval::discordance(scored(Task::kGrasp, a), scored(Task::kHard, a)).ok());
}

TEST(Evaluate, ComparisonTablePrintsWhereTheModelsDisagree) {
  Heads h;
  eval::EmbeddingSet set;
  set.touch = touch_set();
  set.grasp = grasp_set();
  eval::EvalOptions o = model_only_options();
  o.heads.grasp_features = eval::GraspFeatures::kBeforeDuring;
  auto r = eval::evaluate_embeddings(h.metadata(), set, o);
  ASSERT_TRUE(r.ok()) << r.error().message();
  const eval::TaskResult* hard = r->find(Task::kHard, Method::kModelHeads);
  ASSERT_TRUE(hard->available);
  EXPECT_EQ(hard->item_correct.size(), static_cast<size_t>(hard->n));
  const eval::EvalReport* same[] = {&*r, &*r};
  const std::string table = eval::format_table(same, false);
  EXPECT_NE(table.find("right only in [1] / [2] (p)"), std::string::npos) << table;
  EXPECT_NE(table.find("0/0 (1.00)"), std::string::npos) << table;
  EXPECT_NE(eval::report_json(same).find("\"mcnemar_p\""), std::string::npos);
  const eval::EvalReport* one[] = {&*r};
  EXPECT_EQ(eval::format_table(one, false).find("right only in"), std::string::npos);
}

TEST(Evaluate, MixedImagePathSetsReportEachPath) {
  Heads h;
  eval::EmbeddingSet set;
  set.grasp = grasp_set();
  eval::EvalOptions o = model_only_options();
  o.heads.grasp_features = eval::GraspFeatures::kBeforeDuring;
  auto jpeg_only = eval::evaluate_embeddings(h.metadata(), set, o);
  ASSERT_TRUE(jpeg_only.ok()) << jpeg_only.error().message();
  for (const std::string& n : jpeg_only->notes)
    EXPECT_EQ(n.find("by image path"), std::string::npos) << "one path: no note; " << n;
  // Test episodes 4..7: the first and the last take the live path.
  set.grasp->live_path = {0, 0, 0, 0, 1, 0, 0, 1};
  auto mixed = eval::evaluate_embeddings(h.metadata(), set, o);
  ASSERT_TRUE(mixed.ok()) << mixed.error().message();
  const eval::TaskResult* probe = mixed->find(Task::kGrasp, Method::kProbe);
  ASSERT_TRUE(probe->available);
  ASSERT_EQ(probe->item_correct.size(), 4u);
  const int live_hits = probe->item_correct[0] + probe->item_correct[3];
  const int jpeg_hits = probe->item_correct[1] + probe->item_correct[2];
  char want[160];
  std::snprintf(want, sizeof want,
                "grasp linear probe by image path: live path %.1f %% (n=2), dataset JPEG path "
                "%.1f %% (n=2)",
                50.0 * live_hits, 50.0 * jpeg_hits);
  EXPECT_NE(std::find(mixed->notes.begin(), mixed->notes.end(), std::string(want)),
            mixed->notes.end())
      << want;
}

TEST(Evaluate, TaskConventions) {
  EXPECT_EQ(eval::task_class_index(Task::kHard, "HARD").value(), 1);
  EXPECT_EQ(eval::task_class_index(Task::kHard, "soft").value(), 0);
  EXPECT_EQ(eval::task_class_index(Task::kRough, "rough").value(), 1);
  EXPECT_EQ(eval::task_class_index(Task::kGrasp, "true").value(), 1);
  EXPECT_EQ(eval::task_class_index(Task::kGrasp, "falling").value(), 0);
  EXPECT_EQ(eval::task_class_index(Task::kMaterial, "synthetic fabric").value(), 8);
  EXPECT_FALSE(eval::task_class_index(Task::kMaterial, "cheese").ok());
  EXPECT_EQ(eval::task_of_head("hard").value(), Task::kHard);
  EXPECT_EQ(eval::task_of_head("rough_smooth").value(), Task::kRough);
  EXPECT_FALSE(eval::task_of_head("colour").ok());
  auto layout = heads::parse_grasp_layout("finger0.before, B.during");
  ASSERT_TRUE(layout.ok());
  EXPECT_EQ((*layout)[1].finger, 1);
  EXPECT_EQ((*layout)[1].moment, heads::Moment::kDuring);
  EXPECT_FALSE(heads::parse_grasp_layout("C.before").ok());
  EXPECT_EQ(eval::grasp_feature_layout(eval::GraspFeatures::kBeforeAfter),
            "A.before,A.after,B.before,B.after");
}

}  // namespace
}  // namespace tlvlink
