// Press heads (issue 29): the loader reads and validates them, the evaluator computes them on a
// press's peak and first embeddings (after the per-frame heads, which they leave alone), their
// golden outputs are stored and checked, and a metadata rewrite keeps them.
#include <cmath>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "model/tiny_models.h"
#include "support/test_models.h"
#include "tlvlink/heads/evaluator.h"
#include "tlvlink/quantize/model_copy.h"
#include "tlvlink/verify/golden_heads.h"

namespace tlvlink::testing {
namespace {

// Two labels over [peak (2), peak - first (2)]: 2 x 4 weights.
quantize::LinearHeadSpec press_head(std::vector<float> weight,
                                    std::string name = "hard_soft_press") {
  quantize::LinearHeadSpec h{std::move(name), {"soft", "hard"}, std::move(weight), {0.5f, -0.5f}};
  h.features = std::string(kPressFeatures);
  return h;
}

// The tiny model (embedding dim 2) with a per-frame head "hard_soft", `press` and two golden
// pairs (outputs (1.5, -0.5) and (0.5, 0.25) as float32).
TinyInt8Model with_press_heads(std::vector<quantize::LinearHeadSpec> press) {
  TinyInt8Model m;
  m.tweak = [press](quantize::ModelBuilder& b) {
    auto& md = b.metadata();
    md.linear_heads.push_back({"hard_soft", {"soft", "hard"}, {1, 0, 0, 1}, {0, 0}});
    md.press_heads = press;
    for (const auto& e : {std::array<float, 2>{1.5f, -0.5f}, std::array<float, 2>{0.5f, 0.25f}}) {
      std::vector<std::byte> out(2 * sizeof(float));
      std::memcpy(out.data(), e.data(), out.size());
      md.golden.push_back({std::vector<std::byte>(8 * 8 * 3 * 4, std::byte{0}), out});
    }
  };
  return m;
}

// softmax of two logits: p(label 1).
float second(float l0, float l1) { return 1.0f / (1.0f + std::exp(l0 - l1)); }

TEST(PressHeads, LoadAndEvaluateOnPeakAndFirst) {
  auto model = load_model(with_press_heads({press_head({1, 0, 2, 0, 0, 1, 0, 3})}).build());
  ASSERT_NE(model, nullptr);
  const Metadata& md = model->metadata();
  ASSERT_EQ(md.press_heads.size(), 1u);
  EXPECT_EQ(md.press_heads[0].features, kPressFeatures);
  auto h = heads::HeadEvaluator::create(md);
  ASSERT_TRUE(h.ok()) << h.error().message();
  ASSERT_EQ(h->results().size(), 2u);
  EXPECT_EQ(h->per_frame_count(), 1u);
  EXPECT_TRUE(h->has_press());
  EXPECT_EQ(h->results()[1].kind, heads::HeadKind::kPress);
  EXPECT_STREQ(heads::head_kind_name(heads::HeadKind::kPress), "press");
  EXPECT_TRUE(heads::reported_by_default(h->results()[1])) << "no trust record: reported";
  // Peak (2, 1), first (1, 1): features (2, 1, 1, 0). Logits 0.5 + 2 + 2 = 4.5 and
  // -0.5 + 1 + 0 = 0.5 (exact in float).
  const float peak[2] = {2, 1}, first[2] = {1, 1};
  ASSERT_TRUE(h->evaluate_press(peak, first).ok());
  EXPECT_FLOAT_EQ(h->results()[1].logits[0], 4.5f);
  EXPECT_FLOAT_EQ(h->results()[1].logits[1], 0.5f);
  EXPECT_EQ(h->results()[1].top, 0);
  // The per-frame pass leaves the press head's answer as it was.
  const float e[2] = {0, 3};
  ASSERT_TRUE(h->evaluate(e).ok());
  EXPECT_EQ(h->results()[0].top, 1);
  EXPECT_FLOAT_EQ(h->results()[1].logits[0], 4.5f);
  const float three[3] = {1, 2, 3};
  EXPECT_FALSE(h->evaluate_press(three, first).ok()) << "a peak of the wrong size";
}

TEST(PressHeads, GoldenOutputsAreStoredAndChecked) {
  auto model = load_model(with_press_heads({press_head({1, 0, 2, 0, 0, 1, 0, 3})}).build());
  ASSERT_NE(model, nullptr);
  const Metadata& md = model->metadata();
  // Golden output 0 (1.5, -0.5) as the peak, output 1 (0.5, 0.25) as the first frame:
  // features (1.5, -0.5, 1, -0.75); logits 0.5 + 1.5 + 2 = 4 and -0.5 - 0.5 - 2.25 = -3.25.
  ASSERT_EQ(md.golden_press.size(), 2u);
  EXPECT_NEAR(md.golden_press[1], second(4.0f, -3.25f), 1e-7);
  EXPECT_EQ(md.golden[0].head_probabilities.size(), 2u) << "the per-frame head's only";
  auto check = verify::check_golden_heads(*model);
  ASSERT_TRUE(check.ok()) << check.error().message();
  EXPECT_TRUE(check->stored);
  EXPECT_TRUE(check->pass) << check->max_abs_error;
}

TEST(PressHeads, SurviveAMetadataRewriteAndOlderFilesHaveNone) {
  auto model = load_model(with_press_heads({press_head({1, 0, 2, 0, 0, 1, 0, 3})}).build());
  ASSERT_NE(model, nullptr);
  const quantize::MetadataSpec spec = quantize::metadata_spec_from(model->metadata());
  ASSERT_EQ(spec.press_heads.size(), 1u);
  EXPECT_EQ(spec.press_heads[0].features, kPressFeatures);
  EXPECT_EQ(spec.press_heads[0].weight, (std::vector<float>{1, 0, 2, 0, 0, 1, 0, 3}));
  EXPECT_TRUE(spec.linear_heads[0].features.empty());
  auto none = load_model(with_press_heads({}).build());
  ASSERT_NE(none, nullptr);
  EXPECT_TRUE(none->metadata().press_heads.empty());
  EXPECT_TRUE(none->metadata().golden_press.empty());
  auto h = heads::HeadEvaluator::create(none->metadata());
  ASSERT_TRUE(h.ok());
  EXPECT_FALSE(h->has_press());
}

TEST(PressHeads, InconsistentHeadsAreRefusedNamingTheDefect) {
  struct Case {
    const char* what;
    quantize::LinearHeadSpec head;
    const char* says;
  };
  quantize::LinearHeadSpec other = press_head({1, 0, 2, 0, 0, 1, 0, 3});
  other.features = "press.peak";
  quantize::LinearHeadSpec none = other;
  none.features.clear();
  const Case cases[] = {
      {"another feature layout", other, "reads 'press.peak'"},
      {"no feature layout", none, "reads ''"},
      {"one embedding's weights", press_head({1, 0, 0, 1}), "need 8 weights"},
      {"a per-frame head's name", press_head({1, 0, 2, 0, 0, 1, 0, 3}, "hard_soft"),
       "another head has that name"},
      {"a NaN weight", press_head({1, NAN, 2, 0, 0, 1, 0, 3}), "not finite"},
  };
  for (const Case& c : cases) {
    const Error e = load_error(with_press_heads({c.head}).build());
    EXPECT_EQ(e.code(), ErrorCode::kModelInvalidMetadata) << c.what << ": " << e.message();
    EXPECT_NE(std::string(e.message()).find(c.says), std::string::npos)
        << c.what << ": " << e.message();
  }
  // A per-frame head that declares press features is refused too.
  TinyInt8Model m = with_press_heads({});
  const auto base = m.tweak;
  m.tweak = [base](quantize::ModelBuilder& b) {
    base(b);
    b.metadata().linear_heads[0].features = std::string(kPressFeatures);
  };
  const Error e = load_error(m.build());
  EXPECT_NE(std::string(e.message()).find("only a press head"), std::string::npos) << e.message();
}

}  // namespace
}  // namespace tlvlink::testing
