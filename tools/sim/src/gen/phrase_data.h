#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "phrase_data.h is internal to tools/sim: include its public headers instead"
#endif
// The phrase vocabulary and its rules, embedded at build time from tools/sim/data/ by CMake
// (phrase_data.cc.in): the library never reads these files at run time.

#include <string_view>

namespace tlvlink::sim::internal {

extern const std::string_view kPhraseCountsTsv;  // touch100k-phrases.tsv: phrase, count
extern const std::string_view kPhraseRulesTsv;   // phrase-rules.tsv: phrase, facets, rule

}  // namespace tlvlink::sim::internal
