// The rule language is tiny on purpose (a conjunction of key=values tokens per alternative) so
// that every phrase's physics is readable in one line of phrase-rules.tsv.

#include "gen/phrase_vocabulary.h"

#include <charconv>
#include <map>
#include <string>

namespace tlvlink::sim::internal {
namespace {

constexpr std::string_view kCountsFile = "touch100k-phrases.tsv";
constexpr std::string_view kRulesFile = "phrase-rules.tsv";

struct KeyInfo {
  std::string_view name;
  TraitKey key;
  std::vector<std::string_view> values;  // index = TactileTraits::value(key)
};

const std::vector<KeyInfo>& keys() {
  static const std::vector<KeyInfo> k = {
      {"hardness", TraitKey::kHardness, {"soft", "hard"}},
      {"roughness", TraitKey::kRoughness, {"smooth", "mid", "rough", "very"}},
      {"bumpy", TraitKey::kBumpy, {"no", "yes"}},
      {"thermal", TraitKey::kThermal, {"cool", "neutral", "warm"}},
      {"friction", TraitKey::kFriction, {"slippery", "low", "moderate", "grippy"}},
      {"force", TraitKey::kForce, {"light", "medium", "firm"}},
      {"shape", TraitKey::kShape, {"none", "sphere", "cylinder", "flat", "edge"}},
      {"class", TraitKey::kClass, {}},  // filled from the material table
  };
  return k;
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  size_t start = 0;
  while (true) {
    const size_t end = s.find(sep, start);
    parts.push_back(s.substr(start, end == std::string_view::npos ? end : end - start));
    if (end == std::string_view::npos) return parts;
    start = end + 1;
  }
}

std::vector<std::string_view> words_of(std::string_view s) {
  std::vector<std::string_view> w;
  for (std::string_view part : split(s, ' ')) {
    if (!part.empty()) w.push_back(part);
  }
  return w;
}

Error format_error(std::string_view file, int line, const std::string& what) {
  return Error::make(ErrorCode::kFormat, "%.*s line %d: %s", static_cast<int>(file.size()),
                     file.data(), line, what.c_str());
}

// Class name with '_' for ' ' -> id, or -1.
int32_t class_id_of(std::string_view token) {
  std::string name(token);
  for (char& c : name) c = c == '_' ? ' ' : c;
  const MaterialClass* c = find_material_class(name);
  return c ? c->id : -1;
}

class RuleParser {
 public:
  // "@name<TAB>a|b|@other": a named set of classes.
  Status define_set(std::string_view name, std::string_view values, int line) {
    TLV_ASSIGN_OR_RETURN(uint32_t mask, class_mask(values, line));
    sets_[std::string(name)] = mask;
    return {};
  }

  Result<std::vector<PhraseRule>> parse(std::string_view rule, int line) const {
    std::vector<PhraseRule> alternatives;
    if (rule == "-") {
      alternatives.push_back(any());
      return alternatives;
    }
    for (std::string_view alt : split(rule, ';')) {
      PhraseRule r = any();
      const std::vector<std::string_view> tokens = words_of(alt);
      if (tokens.empty()) return format_error(kRulesFile, line, "empty rule alternative");
      for (std::string_view token : tokens) TLV_TRY(apply(token, line, r));
      alternatives.push_back(r);
    }
    return alternatives;
  }

 private:
  static PhraseRule any() {
    PhraseRule r;
    r.allowed.fill(~0u);
    return r;
  }

  Result<uint32_t> class_mask(std::string_view values, int line) const {
    uint32_t mask = 0;
    for (std::string_view v : split(values, '|')) {
      if (!v.empty() && v[0] == '@') {
        const auto it = sets_.find(std::string(v.substr(1)));
        if (it == sets_.end())
          return format_error(kRulesFile, line, "unknown set " + std::string(v));
        mask |= it->second;
        continue;
      }
      const int32_t id = class_id_of(v);
      if (id < 0) return format_error(kRulesFile, line, "unknown class '" + std::string(v) + "'");
      mask |= 1u << id;
    }
    return mask;
  }

  Status apply(std::string_view token, int line, PhraseRule& r) const {
    bool negate = false;
    std::string expanded;
    if (const size_t eq = token.find('='); eq == std::string_view::npos) {
      negate = token[0] == '!';
      const std::string_view word = negate ? token.substr(1) : token;
      if (word == "hard" || word == "soft")
        expanded = "hardness=" + std::string(word);
      else if (word == "rough")
        expanded = "roughness=rough|very";
      else if (word == "smooth")
        expanded = "roughness=smooth";
      else if (word == "bumpy")
        expanded = "bumpy=yes";
      else
        return format_error(kRulesFile, line, "unknown token '" + std::string(token) + "'");
    } else {
      negate = eq > 0 && token[eq - 1] == '!';
      expanded = std::string(token.substr(0, negate ? eq - 1 : eq)) + "=" +
                 std::string(token.substr(eq + 1));
    }
    const std::string_view e = expanded;
    const size_t eq = e.find('=');
    const std::string_view name = e.substr(0, eq), values = e.substr(eq + 1);
    for (const KeyInfo& k : keys()) {
      if (k.name != name) continue;
      uint32_t mask = 0;
      if (k.key == TraitKey::kClass) {
        TLV_ASSIGN_OR_RETURN(mask, class_mask(values, line));
      } else {
        for (std::string_view v : split(values, '|')) {
          size_t i = 0;
          while (i < k.values.size() && k.values[i] != v) ++i;
          if (i == k.values.size()) {
            return format_error(kRulesFile, line,
                                "unknown value '" + std::string(v) + "' of " + std::string(name));
          }
          mask |= 1u << i;
        }
      }
      r.allowed[static_cast<size_t>(k.key)] &= negate ? ~mask : mask;
      return {};
    }
    return format_error(kRulesFile, line, "unknown trait '" + std::string(name) + "'");
  }

  std::map<std::string, uint32_t> sets_;
};

Result<uint32_t> parse_facets(std::string_view list, int line) {
  uint32_t facets = 0;
  const std::span<const std::string_view> names = phrase_facet_names();
  for (std::string_view f : split(list, ',')) {
    size_t i = 0;
    while (i < names.size() && names[i] != f) ++i;
    if (i == names.size())
      return format_error(kRulesFile, line, "unknown facet '" + std::string(f) + "'");
    facets |= 1u << i;
  }
  return facets;
}

struct RuleLine {
  uint32_t facets = 0;
  std::vector<PhraseRule> any_of;
  int line = 0;
  bool used = false;
};

Result<std::map<std::string, RuleLine, std::less<>>> parse_rules(std::string_view tsv) {
  std::map<std::string, RuleLine, std::less<>> rules;
  RuleParser parser;
  int line_no = 0;
  for (std::string_view line : split(tsv, '\n')) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string_view> cols = split(line, '\t');
    if (line[0] == '@') {
      if (cols.size() != 2)
        return format_error(kRulesFile, line_no, "a set needs '@name<TAB>values'");
      TLV_TRY(parser.define_set(cols[0].substr(1), cols[1], line_no));
      continue;
    }
    if (cols.size() != 3) {
      return format_error(kRulesFile, line_no,
                          std::to_string(cols.size()) + " columns (phrase, facets, rule expected)");
    }
    RuleLine r;
    r.line = line_no;
    TLV_ASSIGN_OR_RETURN(r.facets, parse_facets(cols[1], line_no));
    TLV_ASSIGN_OR_RETURN(r.any_of, parser.parse(cols[2], line_no));
    if (!rules.emplace(std::string(cols[0]), std::move(r)).second) {
      return format_error(kRulesFile, line_no, "duplicate phrase '" + std::string(cols[0]) + "'");
    }
  }
  return rules;
}

}  // namespace

Result<std::vector<PhraseInfo>> parse_phrase_vocabulary(std::string_view counts_tsv,
                                                        std::string_view rules_tsv) {
  TLV_ASSIGN_OR_RETURN(auto rules, parse_rules(rules_tsv));
  std::vector<PhraseInfo> phrases;
  int line_no = 0;
  for (std::string_view line : split(counts_tsv, '\n')) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty() || (line_no == 1 && line == "phrase\tcount")) continue;
    const std::vector<std::string_view> cols = split(line, '\t');
    int64_t count = 0;
    const bool numeric =
        cols.size() == 2 &&
        std::from_chars(cols[1].data(), cols[1].data() + cols[1].size(), count).ec == std::errc() &&
        count > 0;
    if (!numeric || words_of(cols[0]).empty()) {
      return format_error(kCountsFile, line_no, "expected '<phrase><TAB><count > 0>'");
    }
    const auto it = rules.find(cols[0]);
    if (it == rules.end()) {
      return format_error(
          kCountsFile, line_no,
          "phrase '" + std::string(cols[0]) + "' has no rule in " + std::string(kRulesFile));
    }
    if (it->second.used)
      return format_error(kCountsFile, line_no, "duplicate phrase '" + std::string(cols[0]) + "'");
    it->second.used = true;
    PhraseInfo p;
    p.text = std::string(cols[0]);
    p.count = count;
    p.words = static_cast<int32_t>(words_of(cols[0]).size());
    p.facets = it->second.facets;
    p.any_of = it->second.any_of;
    phrases.push_back(std::move(p));
  }
  for (const auto& [text, r] : rules) {
    if (!r.used)
      return format_error(kRulesFile, r.line, "phrase '" + text + "' is not in the vocabulary");
  }
  if (phrases.empty()) return format_error(kCountsFile, line_no, "no phrases");
  return phrases;
}

}  // namespace tlvlink::sim::internal
