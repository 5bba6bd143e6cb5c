// Descriptions: the embedded vocabulary and rules, physical consistency of every phrase and
// sentence, the paper's length statistics, phrase frequencies that follow the Touch100k
// counts, determinism, and rule-file errors.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "gen/phrase_vocabulary.h"
#include "support/random.h"
#include "tlvlink/sim/describe.h"

namespace tlvlink::sim {
namespace {

constexpr int kSamples = 2000;
// Paper (Touch100k appendix): sentence-level 61 words; phrase-level 4 phrases of 2 words.
// Tolerances: the generator targets these means; 2000 samples put the sampling error of the
// sentence mean near 0.3 words, so +-4 words / +-0.3 phrases / +-0.3 words per phrase leave room
// only for real drift.
constexpr double kSentenceWords = 61, kSentenceWordsTol = 4;
constexpr double kPhrases = 4, kPhrasesTol = 0.3;
constexpr double kPhraseWords = 2, kPhraseWordsTol = 0.3;

std::set<std::string> tokens(std::string_view text) {
  std::set<std::string> out;
  std::string word;
  for (char ch : text) {
    if (std::isalpha(static_cast<unsigned char>(ch))) {
      word += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    } else if (!word.empty()) {
      out.insert(word);
      word.clear();
    }
  }
  if (!word.empty()) out.insert(word);
  return out;
}

struct Case {
  MaterialSample material;
  TactileTraits traits;
};

Case random_case(testing::Rng& rng) {
  Case c;
  const int32_t cls = rng.int_in(0, kMaterialClassCount - 1);
  c.material = sample_material(cls, rng.engine()()).value();
  const double force = static_cast<double>(std::exp(rng.uniform(std::log(0.5f), std::log(15.0f))));
  constexpr Shape kShapes[] = {Shape::kSphere, Shape::kCylinder, Shape::kFlatPlate,
                               Shape::kBoxEdge};
  c.traits = tactile_traits(c.material, force, kShapes[rng.int_in(0, 3)]);
  return c;
}

// Words that would contradict a label, checked on both description levels.
void expect_consistent(const Case& c, const Description& d) {
  std::string all = d.sentence;
  for (const std::string& p : d.phrases) all += " , " + p;
  const std::set<std::string> words = tokens(all);
  auto forbid = [&](std::initializer_list<const char*> bad, const char* why) {
    for (const char* w : bad) {
      EXPECT_EQ(words.count(w), 0u) << "'" << w << "' contradicts " << why << ": " << all;
    }
  };
  if (c.material.hard)
    forbid({"soft", "plush", "pliable", "supple", "fluffy", "squishy", "cushioned", "yielding"},
           "hard");
  else
    forbid({"hard", "rigid", "unyielding", "stiff", "solid", "metallic", "inflexible", "sturdy",
            "unforgiving"},
           "soft");
  if (c.material.rough == 0) {
    forbid({"rough", "coarse", "gritty", "bumpy", "scratchy", "abrasive", "grainy", "uneven",
            "prickly", "bumps", "splintery"},
           "smooth");
  }
  if (c.material.rough == 1) forbid({"smooth", "silky", "slick", "velvety", "polished"}, "rough");
  if (c.traits.thermal == ThermalFeel::kCool) forbid({"warm"}, "a cool material");
  if (c.traits.thermal == ThermalFeel::kWarm)
    forbid({"cool", "cold", "coolness"}, "a warm material");
  if (c.traits.friction == FrictionFeel::kSlippery) forbid({"tacky", "sticky"}, "low friction");
  if (c.traits.friction == FrictionFeel::kGrippy) forbid({"slippery", "slick"}, "high friction");
  if (c.material.class_id != 4) forbid({"metallic"}, "a non-metal");
}

class DescribeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto d = Describer::create();
    ASSERT_TRUE(d.ok()) << d.error().message();
    describer_ = *d;
  }
  std::shared_ptr<const Describer> describer_;
};

TEST_F(DescribeTest, VocabularyIsTheTouch100kTable) {
  const auto v = describer_->vocabulary();
  ASSERT_EQ(v.size(), 197u);
  EXPECT_EQ(v[0].text, "cool");
  EXPECT_EQ(v[0].count, 40551);
  EXPECT_EQ(v.back().text, "heavy and dense");
  int64_t total = 0;
  for (const PhraseInfo& p : v) {
    EXPECT_FALSE(p.any_of.empty()) << p.text;
    EXPECT_NE(p.facets, 0u) << p.text;
    EXPECT_EQ(p.words, count_words(p.text));
    total += p.count;
  }
  EXPECT_EQ(total, 394846);
  ASSERT_NE(describer_->find("rough and bumpy"), nullptr);
  EXPECT_EQ(describer_->find("rough and bumpy")->count, 929);
  EXPECT_EQ(describer_->find("not a phrase"), nullptr);
}

TEST_F(DescribeTest, EveryPhraseFitsSomeSample) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  std::vector<bool> fits(describer_->vocabulary().size(), false);
  for (int i = 0; i < kSamples; ++i) {
    const Case c = random_case(rng);
    for (size_t p = 0; p < fits.size(); ++p)
      fits[p] = fits[p] || describer_->vocabulary()[p].compatible(c.traits);
  }
  for (size_t p = 0; p < fits.size(); ++p)
    EXPECT_TRUE(fits[p]) << describer_->vocabulary()[p].text << " never fits";
}

TEST_F(DescribeTest, RulesEncodeThePhysics) {
  MaterialSample fabric = sample_material(8, 1).value();  // synthetic fabric: soft
  fabric.sq_um = 20;
  fabric.rough = 1;
  const TactileTraits t = tactile_traits(fabric, 3, Shape::kFlatPlate);
  for (const char* p :
       {"hard", "metallic", "smooth", "cool and hard", "hard and unyielding", "cold"}) {
    EXPECT_FALSE(describer_->find(p)->compatible(t)) << p;
  }
  for (const char* p : {"soft", "rough", "warm", "fibrous", "woven", "flat", "tactile", "dry"}) {
    EXPECT_TRUE(describer_->find(p)->compatible(t)) << p;
  }
}

TEST_F(DescribeTest, DescriptionsNeverContradictThePhysics) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  Description d;
  for (int i = 0; i < kSamples; ++i) {
    const Case c = random_case(rng);
    describer_->describe(c.traits, seed + static_cast<uint64_t>(i), d);
    ASSERT_FALSE(d.phrases.empty());
    for (const std::string& p : d.phrases) {
      const PhraseInfo* info = describer_->find(p);
      ASSERT_NE(info, nullptr) << p << " is not in the vocabulary";
      EXPECT_TRUE(info->compatible(c.traits)) << p;
    }
    std::set<std::string> unique(d.phrases.begin(), d.phrases.end());
    EXPECT_EQ(unique.size(), d.phrases.size()) << "repeated phrase";
    expect_consistent(c, d);
    if (HasFailure()) return;
  }
}

TEST_F(DescribeTest, StatisticsMatchThePaper) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  Description d;
  double sentence_words = 0, phrases = 0, phrase_words = 0;
  std::map<std::string, int64_t> freq;
  for (int i = 0; i < kSamples; ++i) {
    const Case c = random_case(rng);
    describer_->describe(c.traits, seed + static_cast<uint64_t>(i), d);
    sentence_words += count_words(d.sentence);
    phrases += static_cast<double>(d.phrases.size());
    for (const std::string& p : d.phrases) {
      phrase_words += count_words(p);
      ++freq[p];
    }
  }
  const double mean_sentence = sentence_words / kSamples, mean_phrases = phrases / kSamples;
  const double mean_phrase_words = phrase_words / phrases;
  std::printf("over %d samples: sentence %.2f words, %.3f phrases of %.3f words\n", kSamples,
              mean_sentence, mean_phrases, mean_phrase_words);
  EXPECT_NEAR(mean_sentence, kSentenceWords, kSentenceWordsTol);
  EXPECT_NEAR(mean_phrases, kPhrases, kPhrasesTol);
  EXPECT_NEAR(mean_phrase_words, kPhraseWords, kPhraseWordsTol);

  // Spearman rank correlation of generated frequency vs Touch100k count.
  const auto v = describer_->vocabulary();
  std::vector<double> a(v.size()), b(v.size());
  for (size_t i = 0; i < v.size(); ++i) {
    a[i] = static_cast<double>(v[i].count);
    b[i] = static_cast<double>(freq[v[i].text]);
  }
  auto ranks = [](const std::vector<double>& x) {
    std::vector<size_t> idx(x.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](size_t p, size_t q) { return x[p] < x[q]; });
    std::vector<double> r(x.size());
    for (size_t i = 0; i < idx.size();) {  // average ranks of ties
      size_t j = i;
      while (j + 1 < idx.size() && x[idx[j + 1]] == x[idx[i]]) ++j;
      for (size_t k = i; k <= j; ++k) r[idx[k]] = 0.5 * static_cast<double>(i + j);
      i = j + 1;
    }
    return r;
  };
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  double ma = 0, mb = 0;
  for (size_t i = 0; i < ra.size(); ++i) {
    ma += ra[i];
    mb += rb[i];
  }
  ma /= static_cast<double>(ra.size());
  mb /= static_cast<double>(rb.size());
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < ra.size(); ++i) {
    sab += (ra[i] - ma) * (rb[i] - mb);
    saa += (ra[i] - ma) * (ra[i] - ma);
    sbb += (rb[i] - mb) * (rb[i] - mb);
  }
  const double rho = sab / std::sqrt(saa * sbb);
  std::printf(
      "Spearman(generated frequency, Touch100k count) = %.3f; top: cool %lld, rough %lld, hard "
      "%lld, smooth %lld, soft %lld\n",
      rho, static_cast<long long>(freq["cool"]), static_cast<long long>(freq["rough"]),
      static_cast<long long>(freq["hard"]), static_cast<long long>(freq["smooth"]),
      static_cast<long long>(freq["soft"]));
  // Physics constraints reshuffle the tail; the bulk of the ordering must survive.
  EXPECT_GT(rho, 0.5);
}

TEST_F(DescribeTest, SameSeedSameText) {
  const TactileTraits t = tactile_traits(sample_material(15, 3).value(), 4, Shape::kSphere);
  Description a, b, c;
  describer_->describe(t, 77, a);
  describer_->describe(t, 77, b);
  describer_->describe(t, 78, c);
  EXPECT_EQ(a.sentence, b.sentence);
  EXPECT_EQ(a.phrases, b.phrases);
  EXPECT_TRUE(a.sentence != c.sentence || a.phrases != c.phrases);
}

TEST(PhraseRules, MalformedFilesAreErrorsWithLineNumbers) {
  const std::string counts = "phrase\tcount\nsoft\t10\nhard\t5\n";
  struct Bad {
    std::string rules, needle;
  };
  const Bad cases[] = {
      {"soft\thardness\tsoft\n", "'hard' has no rule"},
      {"soft\thardness\tsoft\nhard\thardness\thardish\n", "line 2: unknown token"},
      {"soft\thardness\tsoft\nhard\thardness\tclass=unobtainium\n", "unknown class"},
      {"soft\thardness\tsoft\nhard\thardness\tforce=huge\n", "unknown value 'huge'"},
      {"soft\thardness\tsoft\nhard\tmood\thard\n", "unknown facet"},
      {"soft\thardness\tsoft\nhard\thardness\n", "line 2: 2 columns"},
      {"soft\thardness\tsoft\nhard\thardness\thard\nsoft\thardness\tsoft\n", "line 3: duplicate"},
      {"soft\thardness\tsoft\nhard\thardness\tclass=@missing\n", "unknown set"},
      {"soft\thardness\tsoft\nhard\thardness\thard\nwet\tmoisture\t-\n",
       "'wet' is not in the vocabulary"},
  };
  for (const Bad& b : cases) {
    const auto r = internal::parse_phrase_vocabulary(counts, b.rules);
    ASSERT_FALSE(r.ok()) << b.rules;
    EXPECT_EQ(r.error().code(), ErrorCode::kFormat);
    EXPECT_NE(std::string(r.error().message()).find(b.needle), std::string::npos)
        << r.error().message();
  }
  const auto bad_count =
      internal::parse_phrase_vocabulary("phrase\tcount\nsoft\tmany\n", "soft\thardness\tsoft\n");
  ASSERT_FALSE(bad_count.ok());
  EXPECT_NE(std::string(bad_count.error().message()).find("touch100k-phrases.tsv line 2"),
            std::string::npos);
  const auto good = internal::parse_phrase_vocabulary(
      counts, "@s\tmetal|glass\nsoft\thardness\tsoft ; class=@s\nhard\thardness\t!soft\n");
  ASSERT_TRUE(good.ok()) << good.error().message();
  EXPECT_EQ(good.value()[0].any_of.size(), 2u);
}

}  // namespace
}  // namespace tlvlink::sim
