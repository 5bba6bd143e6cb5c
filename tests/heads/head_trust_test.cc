// Head trust records (issue 16): the loader reads and validates them, old files without them
// still load, and head_trust.h's rule decides from them.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "model/tiny_models.h"
#include "support/test_models.h"
#include "tlvlink/head_trust.h"
#include "tlvlink/heads/evaluator.h"

namespace tlvlink::testing {
namespace {

quantize::HeadTrustSpec record(float accuracy, float majority, int64_t n) {
  quantize::HeadTrustSpec t;
  t.present = true;
  t.accuracy = accuracy;
  t.majority = majority;
  t.n = n;
  t.test_set = "touch: set (touch100k) test split (recorded): 2400 items";
  return t;
}

// A cross-validated record as `heads fit --images` writes it.
quantize::HeadTrustSpec cv_record(float accuracy, float low, float high, float baseline) {
  quantize::HeadTrustSpec t = record(accuracy, 0.5f, 96);
  t.balanced_accuracy = accuracy - 0.01f;
  t.ci_low = low;
  t.ci_high = high;
  t.groups = 6;
  t.baseline_accuracy = baseline;
  t.baseline = "logistic regression on pixels";
  return t;
}

HeadTrust view(float accuracy, float majority, int64_t n) {
  HeadTrust t;
  t.present = true;
  t.accuracy = accuracy;
  t.majority = majority;
  t.n = n;
  return t;
}

// A tiny model whose three kinds of head carry `trust` (or none when !trust.present).
TinyInt8Model with_heads(const quantize::HeadTrustSpec& trust) {
  TinyInt8Model m;
  m.tweak = [trust](quantize::ModelBuilder& b) {
    auto& md = b.metadata();
    quantize::LinearHeadSpec linear{"hard_soft", {"soft", "hard"}, {1, 2, 3, 4}, {0.5f, -0.5f}};
    linear.trust = trust;
    md.linear_heads.push_back(linear);
    quantize::ZeroShotHeadSpec zs{"rough", {"smooth", "rough"}, "{}", {1, 0, 0, 1}, 100};
    zs.trust = trust;
    md.zero_shot_heads.push_back(zs);
    md.has_grasp_head = true;
    md.grasp_head = {"grasp", "A.before,A.during", {1, 2, 3, 4}, 0.25f};
    md.grasp_head.trust = trust;
  };
  return m;
}

TEST(HeadTrust, RecordsRoundTripOnEveryKindOfHead) {
  auto model = load_model(with_heads(record(0.82f, 0.734f, 2160)).build());
  ASSERT_NE(model, nullptr);
  const Metadata& md = model->metadata();
  for (const HeadTrust* t :
       {&md.linear_heads[0].trust, &md.zero_shot_heads[0].trust, &md.grasp_head.trust}) {
    EXPECT_TRUE(t->present);
    EXPECT_FLOAT_EQ(t->accuracy, 0.82f);
    EXPECT_FLOAT_EQ(t->majority, 0.734f);
    EXPECT_EQ(t->n, 2160);
    EXPECT_EQ(t->test_set, "touch: set (touch100k) test split (recorded): 2400 items");
  }
}

TEST(HeadTrust, HeadsWithoutARecordLoadAsUnmeasured) {
  // Files written before the field existed have no trust table: they must still load.
  auto model = load_model(with_heads({}).build());
  ASSERT_NE(model, nullptr);
  const HeadTrust& t = model->metadata().linear_heads[0].trust;
  EXPECT_FALSE(t.present);
  EXPECT_EQ(assess_head(t).level, HeadTrustLevel::kUnmeasured);
  EXPECT_FALSE(head_trusted(t));
}

TEST(HeadTrust, LoaderRejectsRecordsOutsideTheirRange) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const quantize::HeadTrustSpec bad[] = {record(nan, 0.5f, 10), record(0.5f, inf, 10),
                                         record(1.01f, 0.5f, 10), record(0.5f, -0.01f, 10),
                                         record(0.5f, 0.5f, 0)};
  for (const auto& b : bad) {
    auto r = Model::load(with_heads(b).build());
    ASSERT_FALSE(r.ok()) << "accuracy " << b.accuracy << " majority " << b.majority << " n " << b.n;
    EXPECT_EQ(r.error().code(), ErrorCode::kModelInvalidMetadata);
    EXPECT_NE(std::string(r.error().message()).find("trust record"), std::string::npos)
        << r.error().message();
  }
}

TEST(HeadTrust, RuleNeedsTwoPointsAndTwoStandardErrorsOverTheMajority) {
  auto level = [](float accuracy, float majority, int64_t n) {
    return assess_head(view(accuracy, majority, n)).level;
  };
  // n = 2400, majority 0.747: 2 SE = 2 * sqrt(0.747 * 0.253 / 2400) = 0.0178 < 2 points.
  EXPECT_EQ(level(0.80f, 0.747f, 2400), HeadTrustLevel::kTrusted);
  EXPECT_EQ(level(0.76f, 0.747f, 2400), HeadTrustLevel::kUntrusted);   // +1.3: under 2 points
  EXPECT_EQ(level(0.723f, 0.747f, 2400), HeadTrustLevel::kUntrusted);  // below the majority
  // n = 100, majority 0.5: 2 SE = 0.10, so +8 points is noise and +11 is not.
  EXPECT_EQ(level(0.58f, 0.5f, 100), HeadTrustLevel::kUntrusted);
  EXPECT_EQ(level(0.61f, 0.5f, 100), HeadTrustLevel::kTrusted);
  const TrustAssessment a = assess_head(view(0.61f, 0.5f, 100));
  EXPECT_NEAR(a.margin, 0.11, 1e-6);
  EXPECT_NEAR(a.required, 0.10, 1e-9);
  EXPECT_STREQ(head_trust_level_name(HeadTrustLevel::kTrusted), "trusted");
}

TEST(HeadTrust, CrossValidatedRecordsRoundTripAndOldOnesReadAsAbsent) {
  auto model = load_model(with_heads(cv_record(0.9f, 0.8f, 0.97f, 0.6f)).build());
  ASSERT_NE(model, nullptr);
  const HeadTrust& t = model->metadata().linear_heads[0].trust;
  EXPECT_FLOAT_EQ(t.balanced_accuracy, 0.89f);
  EXPECT_FLOAT_EQ(t.ci_low, 0.8f);
  EXPECT_FLOAT_EQ(t.ci_high, 0.97f);
  EXPECT_EQ(t.groups, 6);
  EXPECT_FLOAT_EQ(t.baseline_accuracy, 0.6f);
  EXPECT_EQ(t.baseline, "logistic regression on pixels");
  auto plain = load_model(with_heads(record(0.82f, 0.734f, 2160)).build());
  ASSERT_NE(plain, nullptr);
  const HeadTrust& p = plain->metadata().linear_heads[0].trust;
  EXPECT_EQ(p.ci_low, -1.0f);
  EXPECT_EQ(p.baseline_accuracy, -1.0f);
  EXPECT_EQ(p.groups, 0);
  EXPECT_FALSE(assess_head(p).below_baseline);
}

TEST(HeadTrust, LoaderRejectsCrossValidatedFieldsOutsideTheirRange) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  quantize::HeadTrustSpec outside = cv_record(0.9f, 0.8f, 0.97f, 0.6f);
  outside.ci_low = 0.95f;  // the interval must hold the accuracy
  quantize::HeadTrustSpec half = cv_record(0.9f, 0.8f, 0.97f, 0.6f);
  half.ci_high = -1;  // both ends or neither
  quantize::HeadTrustSpec bad_baseline = cv_record(0.9f, 0.8f, 0.97f, nan);
  quantize::HeadTrustSpec bad_groups = cv_record(0.9f, 0.8f, 0.97f, 0.6f);
  bad_groups.groups = -2;
  for (const auto& b : {outside, half, bad_baseline, bad_groups}) {
    auto r = Model::load(with_heads(b).build());
    ASSERT_FALSE(r.ok()) << "ci " << b.ci_low << ".." << b.ci_high << " baseline "
                         << b.baseline_accuracy << " groups " << b.groups;
    EXPECT_EQ(r.error().code(), ErrorCode::kModelInvalidMetadata);
    EXPECT_NE(std::string(r.error().message()).find("trust record"), std::string::npos);
  }
}

TEST(HeadTrust, AHeadNoBetterThanItsBaselineIsUntrusted) {
  HeadTrust t = view(0.75f, 0.5f, 96);  // well over the majority on its own
  EXPECT_EQ(assess_head(t).level, HeadTrustLevel::kTrusted);
  t.baseline_accuracy = 0.75f;  // pixels do as well
  EXPECT_EQ(assess_head(t).level, HeadTrustLevel::kUntrusted);
  EXPECT_TRUE(assess_head(t).below_baseline);
  t.baseline_accuracy = 0.74f;
  EXPECT_EQ(assess_head(t).level, HeadTrustLevel::kTrusted);
  EXPECT_FALSE(assess_head(t).below_baseline);
}

TEST(HeadTrust, DefaultOutputLeavesOutUntrustedHeadsOnly) {
  // The daemon's default heads (heads::reported_by_default): probe heads unless measured and
  // not better than the majority class; zero-shot heads never by default.
  struct Case {
    quantize::HeadTrustSpec trust;
    bool probe_reported;
  };
  for (const Case& c : {Case{record(0.82f, 0.734f, 2160), true},
                        Case{record(0.74f, 0.734f, 2160), false}, Case{{}, true}}) {
    auto model = load_model(with_heads(c.trust).build());
    ASSERT_NE(model, nullptr);
    auto heads = heads::HeadEvaluator::create(model->metadata());
    ASSERT_TRUE(heads.ok()) << heads.error().message();
    ASSERT_EQ(heads->results().size(), 2u);
    const heads::HeadResult& probe = heads->results()[0];
    const heads::HeadResult& zero_shot = heads->results()[1];
    ASSERT_NE(probe.trust, nullptr);
    EXPECT_EQ(probe.trust->present, c.trust.present);
    EXPECT_EQ(heads::reported_by_default(probe), c.probe_reported)
        << "accuracy " << c.trust.accuracy << " majority " << c.trust.majority;
    EXPECT_FALSE(heads::reported_by_default(zero_shot));
    EXPECT_EQ(&heads->grasp_trust(), &model->metadata().grasp_head.trust);
  }
}

}  // namespace
}  // namespace tlvlink::testing
