#pragma once
// Language statistics of a Touch100k-format set (generated or real), to compare with the
// paper's: sentence-level descriptions average 61 words; phrase-level ones 4 phrases of 2 words.
//  - words: whitespace-separated tokens holding at least one letter or digit ("soft," is one
//    word, a lone "-" none);
//  - phrases: phrase_desc split at commas, trimmed, empty pieces dropped; a phrase's frequency
//    key is its lower-cased text;
//  - words per phrase: over all phrases of the set (not a mean of per-sample means).

#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/datasets/report.h"
#include "tlvlink/error.h"

namespace tlvlink::datasets {

// Paper figures (Touch100k appendix).
inline constexpr double kPaperSentenceWords = 61.0;
inline constexpr double kPaperPhrasesPerSample = 4.0;
inline constexpr double kPaperWordsPerPhrase = 2.0;

struct PhraseCount {
  std::string phrase;
  int64_t count = 0;
};

struct DatasetStats {
  int64_t samples = 0;  // well-formed data_list.json lines
  double sentence_mean_words = 0;
  double phrases_per_sample = 0;
  double words_per_phrase = 0;
  int64_t phrase_total = 0;
  int64_t distinct_phrases = 0;
  std::vector<PhraseCount> top_phrases;           // most frequent first; ties alphabetical
  int64_t missing_touch = 0, missing_vision = 0;  // images data_list.json names but lacks
  LoadReport report;                              // malformed lines (file:line), missing files
};

struct StatsOptions {
  int32_t top_n = 20;       // phrases to list
  bool check_files = true;  // stat touch/<img> and vision/<img>
};

// Fails only when DIR/data_list.json cannot be opened.
Result<DatasetStats> dataset_stats(const std::string& dir, const StatsOptions& options = {});

}  // namespace tlvlink::datasets
