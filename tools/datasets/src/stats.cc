// Language statistics of a Touch100k-format set.

#include "tlvlink/datasets/stats.h"

#include <algorithm>
#include <filesystem>
#include <unordered_map>

#include "line_io.h"
#include "meta.h"
#include "tlvlink/datasets/touch100k.h"
#include "touch_common.h"

namespace tlvlink::datasets {
namespace {

bool is_word_char(char c) {
  const auto u = static_cast<unsigned char>(c);
  return (u >= 'a' && u <= 'z') || (u >= 'A' && u <= 'Z') || (u >= '0' && u <= '9') || u >= 0x80;
}

// Whitespace-separated tokens holding at least one letter or digit.
int64_t count_words(std::string_view text) {
  int64_t words = 0;
  bool in_token = false, token_has_word = false;
  for (size_t i = 0; i <= text.size(); ++i) {
    const bool space =
        i == text.size() || text[i] == ' ' || text[i] == '\t' || text[i] == '\n' || text[i] == '\r';
    if (space) {
      if (in_token && token_has_word) ++words;
      in_token = token_has_word = false;
    } else {
      in_token = true;
      token_has_word = token_has_word || is_word_char(text[i]);
    }
  }
  return words;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return out;
}

}  // namespace

Result<DatasetStats> dataset_stats(const std::string& dir, const StatsOptions& options) {
  TLV_ENSURE(options.top_n >= 0, ErrorCode::kInvalidArgument, "top_n %d < 0", options.top_n);
  LineReader reader;
  TLV_TRY(reader.open(join_path(dir, kTouch100kIndex)));
  DatasetStats stats;
  std::unordered_map<std::string, int64_t> freq;
  int64_t sentence_words = 0, phrase_words = 0;
  std::string line;
  auto malformed = [&](const std::string& why) {
    stats.report.add({ProblemKind::kMalformedLine, reader.path(), reader.line_number(), why});
  };
  while (reader.next(line)) {
    if (is_blank(line)) continue;
    Json j;
    std::string why;
    if (line.size() > kMaxLineBytes || !parse_json(line, j, why)) {
      malformed(why.empty() ? "line too long" : why);
      continue;
    }
    const auto img = j.is_object() ? j.find("img") : j.end();
    const auto sentence = j.is_object() ? j.find("sentence_desc") : j.end();
    const auto phrase = j.is_object() ? j.find("phrase_desc") : j.end();
    if (img == j.end() || !img->is_string() || sentence == j.end() || !sentence->is_string() ||
        phrase == j.end() || !(phrase->is_string() || phrase->is_array())) {
      malformed("needs string img, sentence_desc and phrase_desc");
      continue;
    }
    std::vector<std::string> phrases;
    if (phrase->is_string()) {
      phrases = split_phrases(phrase->get<std::string>());
    } else {
      bool ok = true;
      for (const Json& p : *phrase) {
        if (!p.is_string())
          ok = false;
        else if (!trim(p.get<std::string>()).empty())
          phrases.emplace_back(trim(p.get<std::string>()));
      }
      if (!ok) {
        malformed("phrase_desc array holds a non-string");
        continue;
      }
    }
    const std::string name = img->get<std::string>();
    if (!is_safe_relative_path(name)) {
      malformed("img '" + name + "' is not a relative path inside the set");
      continue;
    }
    ++stats.samples;
    stats.report.count_loaded();
    sentence_words += count_words(sentence->get<std::string>());
    for (const std::string& p : phrases) {
      phrase_words += count_words(p);
      ++freq[lower(p)];
    }
    stats.phrase_total += static_cast<int64_t>(phrases.size());
    if (options.check_files) {
      for (const char* sub : {"touch/", "vision/"}) {
        const std::string path = join_path(dir, sub + name);
        std::error_code ec;
        if (std::filesystem::exists(path, ec)) continue;
        (sub[0] == 't' ? stats.missing_touch : stats.missing_vision) += 1;
        stats.report.add({ProblemKind::kMissingFile, path, 0, "not found"});
      }
    }
  }
  if (stats.samples > 0) {
    const auto n = static_cast<double>(stats.samples);
    stats.sentence_mean_words = static_cast<double>(sentence_words) / n;
    stats.phrases_per_sample = static_cast<double>(stats.phrase_total) / n;
  }
  if (stats.phrase_total > 0)
    stats.words_per_phrase =
        static_cast<double>(phrase_words) / static_cast<double>(stats.phrase_total);
  stats.distinct_phrases = static_cast<int64_t>(freq.size());
  std::vector<PhraseCount> all;
  all.reserve(freq.size());
  for (auto& [phrase, count] : freq) all.push_back({phrase, count});
  const size_t keep = std::min(all.size(), static_cast<size_t>(options.top_n));
  std::partial_sort(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(keep), all.end(),
                    [](const PhraseCount& a, const PhraseCount& b) {
                      return a.count != b.count ? a.count > b.count : a.phrase < b.phrase;
                    });
  all.resize(keep);
  stats.top_phrases = std::move(all);
  return stats;
}

}  // namespace tlvlink::datasets
