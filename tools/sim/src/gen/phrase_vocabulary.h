#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "phrase_vocabulary.h is internal to tools/sim: include its public headers instead"
#endif
// Parsing of the phrase vocabulary (phrase, count) and its rule file (phrase, facets, rule);
// see tools/sim/data/phrase-rules.tsv for the rule language.

#include <string_view>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/sim/describe.h"

namespace tlvlink::sim::internal {

// Joins the two files by phrase, in the order of `counts_tsv`. Errors (kFormat) name the file
// and line: malformed lines, unknown keys/values/sets/facets, duplicates, and phrases present in
// one file but not the other.
Result<std::vector<PhraseInfo>> parse_phrase_vocabulary(std::string_view counts_tsv,
                                                        std::string_view rules_tsv);

}  // namespace tlvlink::sim::internal
