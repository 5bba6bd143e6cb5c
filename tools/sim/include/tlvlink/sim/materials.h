#pragma once
// The material classes as the simulator uses them: the table, samples and labels are
// tools/touch's (touch/materials.h; the datasets and text encoders read them too), named here
// under sim:: for the generators; drawing one object of a class is the simulator's.

#include <cstdint>

#include "tlvlink/error.h"
#include "tlvlink/touch/materials.h"

namespace tlvlink::sim {

using touch::compliant_length_mm;
using touch::find_material_class;
using touch::hard_label;
using touch::kCoolEffusivity;
using touch::kHardModulusPa;
using touch::kMaterialClassCount;
using touch::kPressShapeCount;
using touch::kRoughSqUm;
using touch::kSmoothSqUm;
using touch::kWarmEffusivity;
using touch::material_class;
using touch::material_classes;
using touch::MaterialClass;
using touch::MaterialSample;
using touch::PressShape;
using touch::Range;
using touch::rough_label;
using touch::thermal_feel;
using touch::ThermalFeel;

// Draws one object of class `class_id`: every parameter inside its class range (modulus and Sq
// log-uniform, the others uniform), labels from the rules above. Same (class_id, seed) -> same
// sample. Errors: class_id outside 0..19.
Result<MaterialSample> sample_material(int32_t class_id, uint64_t seed);

}  // namespace tlvlink::sim
