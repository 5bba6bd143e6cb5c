// Phrase-level descriptions: weighted draws from the compatible part of the vocabulary.

#include <algorithm>
#include <array>
#include <cmath>

#include "gen/phrase_data.h"
#include "gen/phrase_vocabulary.h"
#include "gen/rng.h"
#include "tlvlink/sim/describe.h"

namespace tlvlink::sim {
namespace {

// Number of phrases: 2..6 with mean 4.0 (the paper's phrase-level mean).
constexpr std::array<double, 5> kCountWeights = {0.1, 0.2, 0.4, 0.2, 0.1};
constexpr int32_t kMinPhrases = 2;
constexpr int32_t kTextureFacetCap = 2;  // "rough, bumpy" reads naturally; other facets once

int32_t facet_cap(size_t facet) {
  return phrase_facet_names()[facet] == "texture" ? kTextureFacetCap : 1;
}

// The reference population for fit fractions: every class equally, 100 seeded objects each,
// the class's press shapes by weight, and light / medium / firm presses equally.
constexpr int kObjectsPerClass = 100;
constexpr uint64_t kReferenceSeed = 0x7E7E;

void set_fit_fractions(std::vector<PhraseInfo>& phrases) {
  constexpr std::array<Shape, kPressShapeCount> kShapes = {Shape::kSphere, Shape::kCylinder,
                                                           Shape::kFlatPlate, Shape::kBoxEdge};
  constexpr std::array<double, 3> kForces = {1.0, 4.0, 10.0};  // one per ForceFeel level
  std::vector<double> fit(phrases.size(), 0.0);
  double total = 0;
  for (const MaterialClass& c : material_classes()) {
    double shape_sum = 0;
    for (double w : c.press_shapes) shape_sum += w;
    for (int i = 0; i < kObjectsPerClass; ++i) {
      const MaterialSample m =
          sample_material(c.id, kReferenceSeed + static_cast<uint64_t>(i)).value();
      for (size_t s = 0; s < kShapes.size(); ++s) {
        const double w = c.press_shapes[s] / shape_sum;
        if (w <= 0) continue;
        for (double f : kForces) {
          const TactileTraits t = tactile_traits(m, f, kShapes[s]);
          for (size_t p = 0; p < phrases.size(); ++p) fit[p] += phrases[p].compatible(t) ? w : 0.0;
          total += w;
        }
      }
    }
  }
  for (size_t p = 0; p < phrases.size(); ++p) {
    phrases[p].fit_fraction = total > 0 ? fit[p] / total : 1.0;
    const double correction =
        std::min(1.0 / std::max(phrases[p].fit_fraction, 1e-9), Describer::kMaxFitCorrection);
    phrases[p].weight = static_cast<double>(phrases[p].count) * correction *
                        std::pow(Describer::kMultiWordBoost, phrases[p].words - 1);
  }
}

}  // namespace

Result<std::shared_ptr<const Describer>> Describer::create() {
  TLV_ASSIGN_OR_RETURN(
      std::vector<PhraseInfo> phrases,
      internal::parse_phrase_vocabulary(internal::kPhraseCountsTsv, internal::kPhraseRulesTsv));
  set_fit_fractions(phrases);
  auto d = std::shared_ptr<Describer>(new Describer());
  d->phrases_ = std::move(phrases);
  return std::shared_ptr<const Describer>(std::move(d));
}

const PhraseInfo* Describer::find(std::string_view text) const {
  for (const PhraseInfo& p : phrases_) {
    if (p.text == text) return &p;
  }
  return nullptr;
}

void Describer::describe_phrases(const TactileTraits& traits, uint64_t seed,
                                 std::vector<std::string>& out) const {
  internal::Rng rng(
      internal::derive_seed(seed, {internal::tag(internal::Stream::kDescription), 1}));
  const int32_t wanted = kMinPhrases + static_cast<int32_t>(rng.weighted(kCountWeights));
  std::vector<double> weights(phrases_.size(), 0.0);
  for (size_t i = 0; i < phrases_.size(); ++i) {
    if (phrases_[i].compatible(traits)) weights[i] = phrases_[i].weight;
  }
  const size_t facet_count = phrase_facet_names().size();
  std::vector<int32_t> facet_use(facet_count, 0);
  out.clear();
  for (int32_t n = 0; n < wanted; ++n) {
    // Drop phrases whose facets are used up, then draw.
    for (size_t i = 0; i < phrases_.size(); ++i) {
      if (weights[i] == 0) continue;
      for (size_t f = 0; f < facet_count; ++f) {
        if (((phrases_[i].facets >> f) & 1u) && facet_use[f] >= facet_cap(f)) weights[i] = 0;
      }
    }
    double total = 0;
    for (double w : weights) total += w;
    if (total <= 0) break;
    const size_t pick = rng.weighted(weights);
    out.push_back(phrases_[pick].text);
    weights[pick] = 0;
    for (size_t f = 0; f < facet_count; ++f) facet_use[f] += (phrases_[pick].facets >> f) & 1u;
  }
}

void Describer::describe(const TactileTraits& traits, uint64_t seed, Description& out) const {
  describe_phrases(traits, seed, out.phrases);
  describe_sentence(traits, out.phrases, seed, out.sentence);
}

}  // namespace tlvlink::sim
