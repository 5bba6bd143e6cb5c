// tlvlink sim stats DIR (also `tlvlink sim --stats DIR`): language statistics of a
// Touch100k-format set against the paper's 61 / 4 / 2, and its phrase frequency distribution.

#include <nlohmann/json.hpp>

#include <cstdio>
#include <string>

#include "common.h"
#include "sim_commands.h"
#include "tlvlink/datasets/stats.h"

namespace tlvlink::cli {
namespace {

// Problems printed one by one before the summary line says the rest.
constexpr size_t kProblemsShown = 10;

struct StatsFlags {
  std::string dir;
  int top_n = 20;
  bool no_file_check = false;
  bool json = false;
};

void print_json(const datasets::DatasetStats& s) {
  nlohmann::ordered_json top = nlohmann::ordered_json::array();
  for (const auto& p : s.top_phrases) top.push_back({{"phrase", p.phrase}, {"count", p.count}});
  nlohmann::ordered_json j = {{"samples", s.samples},
                              {"sentence_mean_words", s.sentence_mean_words},
                              {"phrases_per_sample", s.phrases_per_sample},
                              {"words_per_phrase", s.words_per_phrase},
                              {"paper",
                               {{"sentence_mean_words", datasets::kPaperSentenceWords},
                                {"phrases_per_sample", datasets::kPaperPhrasesPerSample},
                                {"words_per_phrase", datasets::kPaperWordsPerPhrase}}},
                              {"phrase_total", s.phrase_total},
                              {"distinct_phrases", s.distinct_phrases},
                              {"top_phrases", std::move(top)},
                              {"missing_touch", s.missing_touch},
                              {"missing_vision", s.missing_vision},
                              {"malformed_lines", s.report.malformed_lines()}};
  std::printf("%s\n", j.dump(2).c_str());
}

void print_table(const std::string& dir, const datasets::DatasetStats& s) {
  std::printf("%s: %lld samples\n", dir.c_str(), static_cast<long long>(s.samples));
  std::printf("  %-34s %10s %8s\n", "", "this set", "paper");
  std::printf("  %-34s %10.2f %8.0f\n", "sentence-level: mean words", s.sentence_mean_words,
              datasets::kPaperSentenceWords);
  std::printf("  %-34s %10.2f %8.0f\n", "phrase-level: mean phrases/sample", s.phrases_per_sample,
              datasets::kPaperPhrasesPerSample);
  std::printf("  %-34s %10.2f %8.0f\n", "phrase-level: mean words/phrase", s.words_per_phrase,
              datasets::kPaperWordsPerPhrase);
  std::printf("  %lld phrases, %lld distinct; top %zu:\n", static_cast<long long>(s.phrase_total),
              static_cast<long long>(s.distinct_phrases), s.top_phrases.size());
  for (size_t i = 0; i < s.top_phrases.size(); ++i) {
    const auto& p = s.top_phrases[i];
    const double share = s.phrase_total > 0 ? 100.0 * static_cast<double>(p.count) /
                                                  static_cast<double>(s.phrase_total)
                                            : 0.0;
    std::printf("  %4zu. %-28s %9lld  %5.2f %%\n", i + 1, p.phrase.c_str(),
                static_cast<long long>(p.count), share);
  }
  std::printf("  missing files: %lld touch, %lld vision; malformed lines: %lld\n",
              static_cast<long long>(s.missing_touch), static_cast<long long>(s.missing_vision),
              static_cast<long long>(s.report.malformed_lines()));
}

}  // namespace

int run_sim_stats(const std::string& dir, int top_n, bool check_files, bool json) {
  auto stats = datasets::dataset_stats(dir, {top_n, check_files});
  if (!stats.ok()) return report_error("sim stats", stats.error());
  const auto& problems = stats->report.problems();
  for (size_t i = 0; i < problems.size() && i < kProblemsShown; ++i)
    std::fprintf(stderr, "tlvlink sim stats: %s\n", problems[i].to_string().c_str());
  if (stats->report.problem_count() > 0)
    std::fprintf(stderr, "tlvlink sim stats: %s\n", stats->report.summary().c_str());
  if (json)
    print_json(stats.value());
  else
    print_table(dir, stats.value());
  return kExitOk;
}

void add_sim_stats_command(CLI::App& sim, int& exit_code) {
  auto f = std::make_shared<StatsFlags>();
  CLI::App* cmd =
      sim.add_subcommand("stats",
                         "Language statistics of a Touch100k-format set (generated or real) vs the "
                         "paper's 61 words / 4 phrases / 2 words per phrase, and its top phrases");
  cmd->add_option("dir", f->dir, "Directory holding data_list.json")->required();
  cmd->add_option("--top", f->top_n, "Phrases to list")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  cmd->add_flag("--no-file-check", f->no_file_check, "Do not look for the touch/vision images");
  cmd->add_flag("--json", f->json, "Print JSON instead of a table");
  cmd->footer(kExitCodeFooter);
  cmd->callback(
      [f, &exit_code] { exit_code = run_sim_stats(f->dir, f->top_n, !f->no_file_check, f->json); });
}

}  // namespace tlvlink::cli
