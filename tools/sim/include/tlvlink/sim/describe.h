#pragma once
// Tactile descriptions of a touch sample in the style of Touch100k: a sentence-level paragraph
// (mean ~61 words) and a phrase-level list (mean ~4 phrases of ~2 words), both built from the
// Touch100k phrase vocabulary (tools/sim/data/touch100k-phrases.tsv, embedded at build time)
// and always consistent with the sample's physics: every phrase carries a compatibility rule
// (tools/sim/data/phrase-rules.tsv) over the tactile traits below.

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/sim/materials.h"
#include "tlvlink/sim/scene.h"

namespace tlvlink::sim {

// The categorical traits a description may talk about, derived from the physics.
enum class TraitKey : uint8_t {
  kHardness,
  kRoughness,
  kBumpy,
  kThermal,
  kFriction,
  kForce,
  kShape,
  kClass,
};
inline constexpr size_t kTraitKeyCount = 8;

// Bins: Sq <= 1, <= 5, <= 30, > 30 um; mu < .35, < .5, <= .75, above; F < 2 N, <= 7 N, above.
enum class Roughness : uint8_t { kSmooth, kMid, kRough, kVery };
enum class FrictionFeel : uint8_t { kSlippery, kLow, kModerate, kGrippy };
enum class ForceFeel : uint8_t { kLight, kMedium, kFirm };
enum class ShapeFeel : uint8_t { kNone, kSphere, kCylinder, kFlat, kEdge };

inline constexpr double kVeryRoughSqUm = 30.0;
inline constexpr double kBumpyCorrelationMm = 0.4;  // bumps wider than this feel as bumps
inline constexpr double kSlipperyFriction = 0.35, kLowFriction = 0.5, kGrippyFriction = 0.75;
inline constexpr double kLightForceN = 2.0, kFirmForceN = 7.0;

struct TactileTraits {
  bool hard = false;
  Roughness roughness = Roughness::kMid;
  bool bumpy = false;  // rough with a large correlation length
  ThermalFeel thermal = ThermalFeel::kNeutral;
  FrictionFeel friction = FrictionFeel::kModerate;
  ForceFeel force = ForceFeel::kMedium;
  ShapeFeel shape = ShapeFeel::kNone;
  int32_t class_id = 0;

  uint32_t value(TraitKey key) const;  // the categorical value as a small index
};

// The traits of `material` pressed with `force_n` by an object of `shape`.
TactileTraits tactile_traits(const MaterialSample& material, double force_n, Shape shape);

// One alternative of a phrase's rule: for each trait key, the set of allowed values (bit i =
// value i allowed). A phrase is compatible if any alternative allows every trait value.
struct PhraseRule {
  std::array<uint32_t, kTraitKeyCount> allowed;
};

struct PhraseInfo {
  std::string text;
  int64_t count = 0;  // occurrences in Touch100k (paper's appendix)
  int32_t words = 0;
  uint32_t facets = 0;  // bit set over phrase_facet_names()
  std::vector<PhraseRule> any_of;
  // Fraction of a reference population of touches the phrase fits (Describer::create), and the
  // selection weight derived from it (see Describer::describe_phrases).
  double fit_fraction = 1;
  double weight = 0;
  bool compatible(const TactileTraits& traits) const;
};

std::span<const std::string_view> phrase_facet_names();

struct Description {
  std::string sentence;
  std::vector<std::string> phrases;
};

// Builds descriptions. Immutable after create(); describe() is const and thread-safe.
class Describer {
 public:
  // Parses the embedded vocabulary and rules; an error names the line of a malformed rule or a
  // phrase without one.
  static Result<std::shared_ptr<const Describer>> create();

  std::span<const PhraseInfo> vocabulary() const { return phrases_; }
  // The phrase `text`, or nullptr.
  const PhraseInfo* find(std::string_view text) const;

  // Phrase-level description: 2..6 phrases (mean ~4), each compatible with `traits`, at most one
  // per facet (two for texture), drawn with probability ~ weight = count / fit_fraction *
  // kMultiWordBoost^(words - 1). Dividing by the fit fraction makes a phrase's frequency over
  // many samples follow its Touch100k count although it can only appear where it fits; the
  // boost brings the mean phrase length to the paper's ~2 words (the counts alone give 1.53).
  void describe_phrases(const TactileTraits& traits, uint64_t seed,
                        std::vector<std::string>& out) const;
  // Sentence-level description (mean ~61 words) from varied templates filled with words
  // consistent with `traits`; it weaves in `phrases` (the phrase-level description).
  void describe_sentence(const TactileTraits& traits, std::span<const std::string> phrases,
                         uint64_t seed, std::string& out) const;
  // Both, from one seed.
  void describe(const TactileTraits& traits, uint64_t seed, Description& out) const;

  static constexpr double kMultiWordBoost = 1.6;
  // The fit-fraction correction is capped so that a phrase fitting very few touches does not
  // crowd out everything else on them.
  static constexpr double kMaxFitCorrection = 10;

 private:
  std::vector<PhraseInfo> phrases_;
};

// Word count (whitespace-separated tokens), as the paper's statistics count words.
int32_t count_words(std::string_view text);

}  // namespace tlvlink::sim
