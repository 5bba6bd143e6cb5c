// dataset_stats on a hand-made Touch100k set with known answers.

#include "tlvlink/datasets/stats.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "datasets/samples.h"

namespace tlvlink::datasets {
namespace {

TEST(DatasetStats, KnownAnswers) {
  testing::TempDir tmp;
  testing::write_lines(
      tmp / "data_list.json",
      {
          // 6 words; 2 phrases of 1 word.
          R"({"img": "s/0001.jpg", "sentence_desc": "The surface feels soft and smooth.", "phrase_desc": "soft, smooth"})",
          // 5 words (",", "-" are not words); 3 phrases, 4 words.
          R"({"img": "s/0002.jpg", "sentence_desc": "Hard , cold metal - very rigid", "phrase_desc": "hard, Cold Metal,rigid, "})",
          "",
          // 0 words; an array of phrases: 2 phrases, 3 words.
          R"({"img": "s/0003.jpg", "sentence_desc": "", "phrase_desc": ["Soft", " rough texture "]})",
          R"({"img": 3, "sentence_desc": "x", "phrase_desc": "y"})",  // line 5: malformed
      });
  std::filesystem::create_directories(tmp / "touch/s");
  std::ofstream(tmp / "touch/s/0001.jpg") << "x";
  auto stats = dataset_stats(tmp.path(), {3, true});
  ASSERT_TRUE(stats.ok()) << stats.error().message();
  EXPECT_EQ(stats->samples, 3);
  EXPECT_DOUBLE_EQ(stats->sentence_mean_words, 11.0 / 3.0);
  EXPECT_DOUBLE_EQ(stats->phrases_per_sample, 7.0 / 3.0);
  EXPECT_DOUBLE_EQ(stats->words_per_phrase, 9.0 / 7.0);
  EXPECT_EQ(stats->phrase_total, 7);
  EXPECT_EQ(stats->distinct_phrases, 6);
  ASSERT_EQ(stats->top_phrases.size(), 3u);
  EXPECT_EQ(stats->top_phrases[0].phrase, "soft");
  EXPECT_EQ(stats->top_phrases[0].count, 2);
  EXPECT_EQ(stats->top_phrases[1].phrase, "cold metal");  // ties: alphabetical
  EXPECT_EQ(stats->top_phrases[2].phrase, "hard");
  EXPECT_EQ(stats->missing_touch, 2);
  EXPECT_EQ(stats->missing_vision, 3);
  EXPECT_EQ(stats->report.malformed_lines(), 1);
  EXPECT_EQ(stats->report.missing_files(), 5);
  bool line5 = false;
  for (const auto& p : stats->report.problems())
    line5 = line5 || (p.kind == ProblemKind::kMalformedLine && p.line == 5);
  EXPECT_TRUE(line5);
}

TEST(DatasetStats, EmptyAndMissingSets) {
  testing::TempDir tmp;
  EXPECT_EQ(dataset_stats(tmp.path()).error().code(), ErrorCode::kIo);
  testing::write_lines(tmp / "data_list.json", {});
  auto stats = dataset_stats(tmp.path());
  ASSERT_TRUE(stats.ok());
  EXPECT_EQ(stats->samples, 0);
  EXPECT_DOUBLE_EQ(stats->sentence_mean_words, 0.0);
  EXPECT_DOUBLE_EQ(stats->words_per_phrase, 0.0);
  EXPECT_TRUE(stats->top_phrases.empty());
}

}  // namespace
}  // namespace tlvlink::datasets
