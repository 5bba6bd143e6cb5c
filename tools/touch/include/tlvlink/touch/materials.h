#pragma once
// The 20 Touch-and-Go material classes with per-class ranges of the physical parameters the
// renderer uses, and the hard/soft and rough/smooth labels that follow from the physics. Owned
// here, below the simulator, the datasets and the text encoders, which all read them (the
// simulator samples them: sim/materials.h).
// The table and the reasons for its ranges: tools/sim/REFERENCE.md, "Materials, descriptions,
// grasp episodes".

#include <array>
#include <cstdint>
#include <span>
#include <string_view>

#include "tlvlink/error.h"

namespace tlvlink::touch {

inline constexpr int32_t kMaterialClassCount = 20;
// Label rules (gelsight-sim.md): hard iff E_o > 1 MPa; rough iff Sq > 5 um, smooth iff Sq <= 1 um.
inline constexpr double kHardModulusPa = 1e6;
inline constexpr double kRoughSqUm = 5.0;
inline constexpr double kSmoothSqUm = 1.0;

struct Range {
  double lo = 0, hi = 0;
};

// How a surface feels thermally: set by its thermal effusivity (how fast it draws heat from skin).
enum class ThermalFeel : uint8_t { kCool, kNeutral, kWarm };
inline constexpr double kCoolEffusivity = 1000;  // W s^0.5 / (m^2 K); at or above feels cool
inline constexpr double kWarmEffusivity = 450;   // at or below feels warm (skin is ~1100)

// Shapes an object of a class plausibly presents to the gel when touched.
enum class PressShape : uint8_t { kSphere, kCylinder, kFlat, kEdge };
inline constexpr int32_t kPressShapeCount = 4;

struct MaterialClass {
  int32_t id;             // TAG id 0..19
  std::string_view name;  // "concrete", ..., "others"
  Range modulus_pa;       // sampled log-uniform
  Range poisson;
  Range friction;
  Range sq_um;  // sampled log-uniform
  Range correlation_length_mm;
  Range hurst;
  // Paired "vision" image appearance: base colour (RGB 0..255), colour jitter and a pattern.
  std::array<uint8_t, 3> colour;
  int32_t colour_jitter;
  std::string_view pattern;  // "grain", "weave", "speckle", "bricks", "blades", "cells", ...
  // Added by the generators (beyond the renderer's needs):
  bool tag_hard;              // Touch-and-Go's class-level hard/soft label
  double thermal_effusivity;  // W s^0.5 / (m^2 K), sets the cool/warm description cue
  std::array<double, kPressShapeCount> press_shapes;  // relative weights, indexed by PressShape
  // Thickness of the compliant layer over a rigid backing (fabric on a table, a leather cover,
  // a sheet or stack of paper, a turf of grass), sampled log-uniform; {0, 0} = bulk material.
  // It replaces the object radius as L_o in the compliance split when it is smaller.
  Range layer_mm;
};

std::span<const MaterialClass> material_classes();
// The class with TAG id `id`, or an error (kInvalidArgument) for ids outside 0..19.
Result<const MaterialClass*> material_class(int32_t id);
// The class named `name` ("synthetic fabric"), or nullptr.
const MaterialClass* find_material_class(std::string_view name);

// One sampled material instance (one object).
struct MaterialSample {
  int32_t class_id = 0;
  double modulus_pa = 0, poisson = 0, friction = 0;
  double sq_um = 0, correlation_length_mm = 0, hurst = 0;
  bool hard = false;    // E_o > kHardModulusPa
  int32_t rough = -1;   // 1 rough (Sq > 5 um), 0 smooth (Sq <= 1 um), -1 in between
  double layer_mm = 0;  // compliant layer thickness, 0 = bulk (see MaterialClass)
  // Vision appearance of this object: the class colour after jitter.
  std::array<uint8_t, 3> colour = {128, 128, 128};
};

// The labels the physics gives (the only place they are computed).
inline bool hard_label(double modulus_pa) { return modulus_pa > kHardModulusPa; }
inline int32_t rough_label(double sq_um) {
  return sq_um > kRoughSqUm ? 1 : (sq_um <= kSmoothSqUm ? 0 : -1);
}
ThermalFeel thermal_feel(const MaterialClass& c);

// L_o of the compliance split for this material on an object of local radius `radius_mm`: the
// radius for bulk materials, the compliant layer when it is thinner.
inline double compliant_length_mm(const MaterialSample& m, double radius_mm) {
  return m.layer_mm > 0 && m.layer_mm < radius_mm ? m.layer_mm : radius_mm;
}

}  // namespace tlvlink::touch
