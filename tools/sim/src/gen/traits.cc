// Tactile traits: the physics of a sample binned into the categories descriptions talk about.

#include <algorithm>

#include "tlvlink/sim/describe.h"

namespace tlvlink::sim {
namespace {

constexpr std::string_view kFacetNames[] = {"temp",   "hardness", "texture",  "friction",
                                            "shape",  "material", "moisture", "touch",
                                            "weight", "form",     "feel"};

ShapeFeel shape_feel(Shape shape) {
  switch (shape) {
    case Shape::kNone: return ShapeFeel::kNone;
    case Shape::kSphere:
    case Shape::kPoint: return ShapeFeel::kSphere;
    case Shape::kCylinder: return ShapeFeel::kCylinder;
    case Shape::kFlatPlate:
    case Shape::kHeightMap: return ShapeFeel::kFlat;
    case Shape::kBoxEdge: return ShapeFeel::kEdge;
  }
  return ShapeFeel::kNone;
}

}  // namespace

std::span<const std::string_view> phrase_facet_names() { return kFacetNames; }

uint32_t TactileTraits::value(TraitKey key) const {
  switch (key) {
    case TraitKey::kHardness: return hard ? 1 : 0;
    case TraitKey::kRoughness: return static_cast<uint32_t>(roughness);
    case TraitKey::kBumpy: return bumpy ? 1 : 0;
    case TraitKey::kThermal: return static_cast<uint32_t>(thermal);
    case TraitKey::kFriction: return static_cast<uint32_t>(friction);
    case TraitKey::kForce: return static_cast<uint32_t>(force);
    case TraitKey::kShape: return static_cast<uint32_t>(shape);
    case TraitKey::kClass: return static_cast<uint32_t>(std::clamp(class_id, 0, 31));
  }
  return 0;
}

TactileTraits tactile_traits(const MaterialSample& m, double force_n, Shape shape) {
  TactileTraits t;
  t.hard = m.hard;
  if (m.rough == 0)
    t.roughness = Roughness::kSmooth;
  else if (m.rough < 0)
    t.roughness = Roughness::kMid;
  else
    t.roughness = m.sq_um > kVeryRoughSqUm ? Roughness::kVery : Roughness::kRough;
  t.bumpy = m.rough == 1 && m.correlation_length_mm >= kBumpyCorrelationMm;
  const Result<const MaterialClass*> cls = material_class(m.class_id);
  t.thermal = cls.ok() ? thermal_feel(*cls.value()) : ThermalFeel::kNeutral;
  if (m.friction < kSlipperyFriction)
    t.friction = FrictionFeel::kSlippery;
  else if (m.friction < kLowFriction)
    t.friction = FrictionFeel::kLow;
  else if (m.friction <= kGrippyFriction)
    t.friction = FrictionFeel::kModerate;
  else
    t.friction = FrictionFeel::kGrippy;
  if (force_n < kLightForceN)
    t.force = ForceFeel::kLight;
  else if (force_n <= kFirmForceN)
    t.force = ForceFeel::kMedium;
  else
    t.force = ForceFeel::kFirm;
  t.shape = shape_feel(shape);
  t.class_id = m.class_id;
  return t;
}

bool PhraseInfo::compatible(const TactileTraits& traits) const {
  for (const PhraseRule& r : any_of) {
    bool ok = true;
    for (size_t k = 0; k < kTraitKeyCount && ok; ++k) {
      ok = (r.allowed[k] >> traits.value(static_cast<TraitKey>(k))) & 1u;
    }
    if (ok) return true;
  }
  return false;
}

int32_t count_words(std::string_view text) {
  int32_t words = 0;
  bool in_word = false;
  for (char c : text) {
    const bool space = c == ' ' || c == '\t' || c == '\n' || c == '\r';
    if (!space && !in_word) ++words;
    in_word = !space;
  }
  return words;
}

}  // namespace tlvlink::sim
