// The built-in hashing text encoder, TLV-Link text features and the zero-shot prompt sets.

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "tlvlink/text/text_encoder.h"

namespace tlvlink::text {
namespace {

// Embeddings are computed in double and rounded to float once: unit length to float precision.
constexpr double kUnitNormTolerance = 1e-6;

double dot(const std::vector<float>& a, const std::vector<float>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += static_cast<double>(a[i]) * static_cast<double>(b[i]);
  return s;
}

std::unique_ptr<TextEncoder> encoder(int32_t dim = 128, uint64_t seed = 7) {
  auto e = make_hashing_text_encoder({dim, seed});
  EXPECT_TRUE(e.ok()) << e.error().message();
  return std::move(*e);
}

std::vector<float> embed(TextEncoder& e, const std::string& text) {
  auto r = e.embed_sentence("", text);
  EXPECT_TRUE(r.ok()) << r.error().message();
  return r.ok() ? *r : std::vector<float>{};
}

TEST(HashingTextEncoder, RejectsDimensionsOutsideTheDocumentedRange) {
  EXPECT_FALSE(make_hashing_text_encoder({kMinTextDim - 1, 1}).ok());
  EXPECT_FALSE(make_hashing_text_encoder({kMaxTextDim + 1, 1}).ok());
  EXPECT_TRUE(make_hashing_text_encoder({kMinTextDim, 1}).ok());
}

TEST(HashingTextEncoder, IsDeterministicUnitLengthAndSeeded) {
  auto a = encoder(), b = encoder(), other_seed = encoder(128, 8);
  const std::string text = "A soft, slightly rough fabric that yields under the gel.";
  const auto ea = embed(*a, text);
  ASSERT_EQ(ea.size(), 128u);
  EXPECT_EQ(ea, embed(*b, text));
  EXPECT_NEAR(dot(ea, ea), 1.0, kUnitNormTolerance);
  EXPECT_NE(ea, embed(*other_seed, text));
  EXPECT_EQ(a->description(), "hashing-v1(dim=128,seed=7)");
}

TEST(HashingTextEncoder, IgnoresCaseAndPunctuation) {
  auto e = encoder();
  EXPECT_EQ(embed(*e, "Soft fabric!"), embed(*e, "soft   fabric"));
}

TEST(HashingTextEncoder, EmptyOrWordlessTextIsAnError) {
  auto e = encoder();
  for (const char* text : {"", "  ,.;!  "}) {
    auto r = e->embed_prompt(text);
    ASSERT_FALSE(r.ok()) << "text: '" << text << "'";
    EXPECT_NE(std::string(r.error().message()).find("no words"), std::string::npos);
  }
}

// What the encoder can capture: shared words and word forms. (What it cannot - synonyms,
// negation - is documented in tools/text/README.md, not tested as a virtue.)
TEST(HashingTextEncoder, SharedWordsAndStemsAreCloserThanUnrelatedText) {
  auto e = encoder();
  const auto soft_fabric = embed(*e, "soft fabric");
  EXPECT_GT(dot(soft_fabric, embed(*e, "soft cotton fabric")),
            dot(soft_fabric, embed(*e, "hard metal plate")) + 0.3);
  const auto rough = embed(*e, "rough");
  EXPECT_GT(dot(rough, embed(*e, "roughness")), dot(rough, embed(*e, "smooth")) + 0.2);
}

TEST(TextFeature, IsTheSumOfTheNormalisedSentenceAndPhraseEmbeddings) {
  auto e = encoder();
  auto f = text_feature(*e, "k", "It feels soft and warm.", "soft, warm");
  ASSERT_TRUE(f.ok()) << f.error().message();
  const auto s = embed(*e, "It feels soft and warm.");
  const auto p = embed(*e, "soft, warm");
  for (size_t i = 0; i < s.size(); ++i) EXPECT_FLOAT_EQ((*f)[i], s[i] + p[i]);
  EXPECT_FALSE(text_feature(*e, "k", "fine", "").ok());
}

TEST(PromptSets, FollowThePaperAndTheDatasetsLabelOrder) {
  const PromptSet material = material_prompts();
  ASSERT_EQ(material.class_names.size(), 20u);
  EXPECT_EQ(material.class_names[0], "concrete");
  EXPECT_EQ(material.class_names[19], "others");
  EXPECT_EQ(
      material.prompts_for(4),
      std::vector<std::string>{"the object being touched is metal, it is an image of metal."});
  const PromptSet hard = hardness_prompts();
  EXPECT_EQ(hard.class_names, (std::vector<std::string>{"soft", "hard"}));  // label 1 = hard
  EXPECT_EQ(
      hard.prompts_for(1)[0],
      "the object being touched feels hard , the surface show sort of hardness when touched.");
  EXPECT_EQ(roughness_prompts().prompts_for(0)[0],
            "the object being touched feels smooth, the surface show sort of smoothness.");
  const PromptSet grasp = grasp_prompts();
  EXPECT_EQ(grasp.prompts_for(1)[0], "the object being touched is lifted in the air.");
  EXPECT_EQ(grasp.prompts_for(0)[0], "the object being touched is falling on the ground.");
}

TEST(ZeroShotMatrix, HasUnitRowsPerClassAndPicksTheMatchingDescription) {
  auto e = encoder();
  auto m = zero_shot_matrix(*e, hardness_prompts());
  ASSERT_TRUE(m.ok()) << m.error().message();
  ASSERT_EQ(m->size(), 2u * 128u);
  const std::vector<float> soft_row(m->begin(), m->begin() + 128);
  const std::vector<float> hard_row(m->begin() + 128, m->end());
  EXPECT_NEAR(dot(soft_row, soft_row), 1.0, kUnitNormTolerance);
  EXPECT_NEAR(dot(hard_row, hard_row), 1.0, kUnitNormTolerance);
  auto y = text_feature(*e, "k", "The surface feels soft and yields; a sense of softness.",
                        "soft, yielding");
  ASSERT_TRUE(y.ok());
  EXPECT_GT(dot(*y, soft_row), dot(*y, hard_row));
  auto material = zero_shot_matrix(*e, material_prompts());
  ASSERT_TRUE(material.ok());
  EXPECT_EQ(material->size(), 20u * 128u);
}

}  // namespace
}  // namespace tlvlink::text
