// Linear probes: a known linear separation is recovered, fits are deterministic, the folded
// standardisation is exact, validation by group, and bad inputs are errors.

#include <array>
#include <cfloat>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/heads/grasp_layout.h"
#include "tlvlink/heads/head_math.h"

#include "support/random.h"
#include "tlvlink/eval/probe.h"

namespace tlvlink {
namespace {

using eval::FittedProbe;
using eval::ProbeData;
using eval::ProbeOptions;

// Synthetic embeddings: `classes` centres on the axes of R^dim scaled by kSeparation, plus a
// per-dimension offset and scale (so standardisation matters), plus noise bounded by kNoise in
// every coordinate. Class c's points satisfy x_c - x_k >= kSeparation - 2 kNoise > 0 along
// axis c, so the classes are linearly separable with a wide margin.
constexpr float kSeparation = 4.0f;
constexpr float kNoise = 0.5f;

struct Synthetic {
  std::vector<float> x;
  std::vector<int32_t> y;
  std::vector<std::string> groups;
};

Synthetic make_data(testing::Rng& rng, int32_t classes, int32_t dim, int32_t per_class,
                    int32_t groups_per_class, const std::string& group_prefix) {
  Synthetic s;
  for (int32_t c = 0; c < classes; ++c) {
    for (int32_t i = 0; i < per_class; ++i) {
      for (int32_t j = 0; j < dim; ++j) {
        const float centre = j == c ? kSeparation : 0.0f;
        const float offset = 3.0f + static_cast<float>(j);  // non-zero mean per dimension
        const float scale = 0.5f + 0.25f * static_cast<float>(j % 4);
        s.x.push_back(offset + scale * (centre + rng.uniform(-kNoise, kNoise)));
      }
      s.y.push_back(c);
      s.groups.push_back(group_prefix + std::to_string(c) + "_" +
                         std::to_string(i % groups_per_class));
    }
  }
  return s;
}

double accuracy(const FittedProbe& p, const Synthetic& s) {
  const auto dim = static_cast<size_t>(p.dim);
  std::vector<float> logits(static_cast<size_t>(p.classes));
  int64_t correct = 0;
  for (size_t i = 0; i < s.y.size(); ++i) {
    heads::linear_logits(p.weight, p.bias, std::span<const float>(s.x).subspan(i * dim, dim),
                         logits);
    correct += heads::argmax(logits) == s.y[i] ? 1 : 0;
  }
  return static_cast<double>(correct) / static_cast<double>(s.y.size());
}

TEST(Probe, RecoversALinearSeparation) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  constexpr int32_t kClasses = 5, kDim = 12;
  const Synthetic train = make_data(rng, kClasses, kDim, 40, 4, "train");
  const Synthetic test = make_data(rng, kClasses, kDim, 20, 2, "test");
  ProbeData d{train.x, kDim, train.y, kClasses, train.groups, {}};
  auto p = eval::fit_probe(d, {});
  ASSERT_TRUE(p.ok()) << p.error().message();
  // Separable with a margin of 3 noise widths along the class axis: a converged fit at any l2 of
  // the default grid (each checked below) classifies every training and held-out point
  // correctly, so whichever l2 validation picks, accuracy is exactly 1.
  for (double l2 : ProbeOptions{}.l2_grid) {
    eval::LogisticOptions lo;
    lo.l2 = l2;
    auto q = eval::fit_logistic(d, lo);
    ASSERT_TRUE(q.ok()) << q.error().message();
    EXPECT_EQ(accuracy(*q, test), 1.0) << "l2 " << l2;
  }
  EXPECT_EQ(p->train_accuracy, 1.0);
  EXPECT_EQ(accuracy(*p, train), 1.0);
  EXPECT_EQ(accuracy(*p, test), 1.0);
  EXPECT_EQ(p->validation_accuracy.size(), ProbeOptions{}.l2_grid.size());
  EXPECT_GT(p->validation_rows, 0);
  EXPECT_EQ(p->validation_groups, 4);  // round(20 groups * 0.2)
  EXPECT_EQ(p->train_groups, 20);
  EXPECT_TRUE(p->note.empty()) << p->note;
}

TEST(Probe, DeterministicBitForBit) {
  testing::Rng rng(7);
  const Synthetic s = make_data(rng, 3, 8, 30, 3, "g");
  ProbeData d{s.x, 8, s.y, 3, s.groups, {}};
  auto a = eval::fit_probe(d, {});
  auto b = eval::fit_probe(d, {});
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->weight, b->weight);
  EXPECT_EQ(a->bias, b->bias);
  EXPECT_EQ(a->l2, b->l2);
  EXPECT_EQ(a->iterations, b->iterations);
}

// Folding: W' = W / std, b' = b - W' mean, applied to the raw x in float, against the head
// applied to z = (x - mean) / std in double. Rounding W', b' and the float accumulation each
// cost <= FLT_EPSILON relative per term, over dim + 2 terms: the error stays below
// kFoldRelTolerance times the sum of the absolute terms.
constexpr double kFoldRelTolerance = 4 * (16 + 2) * static_cast<double>(FLT_EPSILON);

TEST(Probe, FoldedStandardisationIsExact) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  constexpr int32_t kDim = 16, kClasses = 4, kRows = 50;
  std::vector<float> x(kRows * kDim);
  for (size_t i = 0; i < x.size(); ++i)
    x[i] = rng.normal(5.0f * static_cast<float>(i % kDim), 3.0f);
  for (int32_t r = 0; r < kRows; ++r)
    x[static_cast<size_t>(r * kDim + 3)] = 2.5f;  // constant column
  const eval::Standardisation s = eval::standardisation_of(x, kDim);
  EXPECT_EQ(s.std[3], 1.0);  // a constant column is centred, not scaled
  std::vector<double> w(kClasses * kDim), b(kClasses);
  for (double& v : w) v = static_cast<double>(rng.normal(0, 1));
  for (double& v : b) v = static_cast<double>(rng.normal(0, 1));
  std::vector<float> fw, fb;
  eval::fold_standardisation(s, w, b, kClasses, fw, fb);
  std::vector<float> logits(kClasses);
  for (int32_t r = 0; r < kRows; ++r) {
    const std::span<const float> row = std::span<const float>(x).subspan(r * kDim, kDim);
    heads::linear_logits(fw, fb, row, logits);
    for (int32_t k = 0; k < kClasses; ++k) {
      double exact = b[static_cast<size_t>(k)],
             magnitude = std::fabs(static_cast<double>(fb[static_cast<size_t>(k)]));
      for (int32_t j = 0; j < kDim; ++j) {
        const auto kj = static_cast<size_t>(k * kDim + j);
        const double z =
            (static_cast<double>(row[static_cast<size_t>(j)]) - s.mean[static_cast<size_t>(j)]) /
            s.std[static_cast<size_t>(j)];
        exact += w[kj] * z;
        magnitude += std::fabs(static_cast<double>(fw[kj]) *
                               static_cast<double>(row[static_cast<size_t>(j)]));
      }
      EXPECT_NEAR(static_cast<double>(logits[static_cast<size_t>(k)]), exact,
                  kFoldRelTolerance * magnitude)
          << "row " << r << " class " << k;
    }
  }
}

TEST(Probe, OneGroupMeansNoValidationSplit) {
  testing::Rng rng(3);
  Synthetic s = make_data(rng, 2, 4, 10, 1, "g");
  for (std::string& g : s.groups) g = "same";
  auto p = eval::fit_probe({s.x, 4, s.y, 2, s.groups, {}}, {});
  ASSERT_TRUE(p.ok()) << p.error().message();
  EXPECT_TRUE(p->validation_accuracy.empty());
  EXPECT_EQ(p->l2, eval::kFallbackL2);
  EXPECT_NE(p->note.find("no validation split"), std::string::npos) << p->note;
}

TEST(Probe, BadInputsAreErrors) {
  std::vector<float> x = {1, 2, 3, 4};
  std::vector<int32_t> y = {0, 2};
  {
    auto p = eval::fit_probe({x, 2, y, 2, {}, {}}, {});
    ASSERT_FALSE(p.ok());
    EXPECT_NE(std::string(p.error().message()).find("label 2 outside"), std::string::npos);
  }
  y = {0, 1};
  x[1] = NAN;
  EXPECT_EQ(eval::fit_probe({x, 2, y, 2, {}, {}}, {}).error().code(), ErrorCode::kNonFiniteValue);
  x[1] = 0;
  // 4 values are not 2 rows of 3.
  EXPECT_EQ(eval::fit_probe({x, 3, y, 2, {}, {}}, {}).error().code(), ErrorCode::kShapeMismatch);
  ProbeOptions o;
  o.l2_grid.clear();
  EXPECT_EQ(eval::fit_probe({x, 2, y, 2, {}, {}}, o).error().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(eval::fit_probe({{}, 2, {}, 2, {}, {}}, {}).error().code(),
            ErrorCode::kInvalidArgument);
}

// Two views of each touch: feature 0 carries the class weakly and is the same in both views;
// feature 1 carries it strongly but a "codec" moves it between the views. The view penalty must
// move the head onto feature 0, so the two views of a held-out touch get the same answer more
// often, at some cost in accuracy.
struct TwoViews {
  std::vector<float> x;  // rows 2i and 2i + 1: the two views of touch i
  std::vector<int32_t> y;
  std::vector<std::string> groups;
  std::vector<std::array<int64_t, 2>> pairs;
};

TwoViews make_two_views(testing::Rng& rng, int32_t touches) {
  TwoViews t;
  for (int32_t i = 0; i < touches; ++i) {
    const int32_t label = i % 2;
    const float sign = label == 1 ? 1.0f : -1.0f;
    const float steady = sign + rng.normal(0.0f, 1.0f);
    const float moved = sign + rng.normal(0.0f, 0.3f);
    for (int32_t view = 0; view < 2; ++view) {
      t.x.push_back(steady);
      t.x.push_back(moved + (view == 1 ? rng.normal(0.0f, 0.8f) : 0.0f));
      t.y.push_back(label);
      t.groups.push_back("touch" + std::to_string(i / 4));
    }
    t.pairs.push_back({2 * i, 2 * i + 1});
  }
  return t;
}

double view_agreement(const FittedProbe& p, const TwoViews& t) {
  std::vector<float> a(2), b(2);
  int64_t same = 0;
  const std::span<const float> x(t.x);
  for (const auto& [i, j] : t.pairs) {
    heads::linear_logits(p.weight, p.bias, x.subspan(static_cast<size_t>(i) * 2, 2), a);
    heads::linear_logits(p.weight, p.bias, x.subspan(static_cast<size_t>(j) * 2, 2), b);
    same += heads::argmax(a) == heads::argmax(b) ? 1 : 0;
  }
  return static_cast<double>(same) / static_cast<double>(t.pairs.size());
}

TEST(Probe, TheViewPenaltyMakesTwoViewsOfATouchAgree) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  const TwoViews train = make_two_views(rng, 800), test = make_two_views(rng, 800);
  ProbeData d{train.x, 2, train.y, 2, train.groups, train.pairs};
  ProbeOptions o;
  o.l2_grid = {1e-3};
  auto plain = eval::fit_probe(d, o);
  o.view_weight_grid = {100};
  auto steady = eval::fit_probe(d, o);
  ASSERT_TRUE(plain.ok() && steady.ok());
  // Weight on the moved feature relative to the steady one (raw-form head: w_true - w_false).
  auto ratio = [](const FittedProbe& p) {
    return std::fabs((p.weight[3] - p.weight[1]) / (p.weight[2] - p.weight[0]));
  };
  EXPECT_GT(ratio(*plain), 1.0);  // without it the strong, moved feature dominates
  EXPECT_LT(ratio(*steady), 0.1);
  // On 800 held-out touches the views of 5-7 % disagree without the penalty (seeds 1-8: the
  // moved feature's view noise crosses the boundary); with it the moved feature barely counts,
  // so they agree but for a few; 0.04 is ~4 binomial SEs (~0.009) of margin.
  const double before = view_agreement(*plain, test), after = view_agreement(*steady, test);
  EXPECT_GT(after, before + 0.04) << before << " -> " << after;
  EXPECT_GT(after, 0.97);
  // A grid: by accuracy the plain fit wins; asked for agreement, the smallest weight that
  // reaches it on the validation pairs.
  o.l2_grid = {1e-3, 1e-1};
  o.view_weight_grid = {100, 0};
  auto by_accuracy = eval::fit_probe(d, o);
  o.min_view_agreement = 0.97;
  auto by_agreement = eval::fit_probe(d, o);
  ASSERT_TRUE(by_accuracy.ok() && by_agreement.ok());
  ASSERT_EQ(by_accuracy->view_trials.size(), 2u);
  EXPECT_EQ(by_accuracy->view_trials[0].view_weight, 0);  // tried in ascending order
  EXPECT_GT(by_accuracy->view_trials[0].accuracy, by_accuracy->view_trials[1].accuracy);
  EXPECT_LT(by_accuracy->view_trials[0].agreement, 0.97);
  EXPECT_GE(by_accuracy->view_trials[1].agreement, 0.97);
  EXPECT_EQ(by_accuracy->view_weight, 0);
  EXPECT_EQ(by_agreement->view_weight, 100);
  // Pairs are checked like every other input.
  std::vector<std::array<int64_t, 2>> bad = {{0, static_cast<int64_t>(train.y.size())}};
  const auto refused = eval::fit_probe({train.x, 2, train.y, 2, train.groups, bad}, o);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(std::string(refused.error().message()).find("view pair"), std::string::npos);
}

}  // namespace
}  // namespace tlvlink
