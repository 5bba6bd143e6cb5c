// Grasp objects are everyday graspable things (Feel's objects): the TAG classes one can pick up,
// with a rounded, cylindrical or flat face under the fingers.

#include "gen/grasp_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "tlvlink/sim/generate.h"
#include "tlvlink/sim/materials.h"

namespace tlvlink::sim {
namespace internal {
namespace {

// plastic, glass, wood, metal, tile, leather, synthetic fabric, natural fabric, rubber, paper,
// rock, others.
constexpr int32_t kGraspableClasses[] = {1, 2, 3, 4, 6, 7, 8, 9, 10, 11, 15, 19};
constexpr double kFlatLocalRadiusMm = 30.0;  // L_o of a flat face in the compliance split

}  // namespace

std::span<const int32_t> graspable_classes() { return kGraspableClasses; }

double sample_mass(Rng& rng) { return rng.log_uniform(kMassMinKg, kMassMaxKg); }

void sample_lift(Rng& rng, double& com_offset_mm, double& lift_accel_mps2) {
  com_offset_mm = rng.uniform(0, kComOffsetMaxMm);
  lift_accel_mps2 = rng.uniform(0, kLiftAccelMax);
}

GraspObject sample_grasp_object(uint64_t seed, int64_t object_index) {
  Rng rng(derive_seed(seed, {tag(Stream::kObject), static_cast<uint64_t>(object_index)}));
  GraspObject o;
  const int32_t cls =
      kGraspableClasses[rng.int_in(0, static_cast<int32_t>(std::size(kGraspableClasses)) - 1)];
  o.material = sample_material(cls, rng.next()).value();  // cls is a valid id
  const double shape = rng.uniform();
  if (shape < 0.35) {
    o.geometry.shape = Shape::kSphere;
    o.geometry.radius_mm = rng.log_uniform(10, 60);
    o.mechanics.local_radius_mm = compliant_length_mm(o.material, o.geometry.radius_mm);
  } else if (shape < 0.75) {
    o.geometry.shape = Shape::kCylinder;
    o.geometry.radius_mm = rng.log_uniform(8, 50);
    o.geometry.length_mm = rng.uniform(60, 200);
    o.geometry.angle_deg = (rng.bernoulli(0.5) ? 0.0 : 90.0) + rng.uniform(-10, 10);
    o.mechanics.local_radius_mm = compliant_length_mm(o.material, o.geometry.radius_mm);
  } else {
    o.geometry.shape = Shape::kFlatPlate;
    o.mechanics.local_radius_mm = compliant_length_mm(o.material, kFlatLocalRadiusMm);
  }
  o.mechanics.modulus_pa = o.material.modulus_pa;
  o.mechanics.poisson = o.material.poisson;
  o.mechanics.layer_mm = o.material.layer_mm;
  o.mass_kg = sample_mass(rng);
  o.texture_seed = rng.next();
  return o;
}

GraspSetup sample_grasp_setup(uint64_t seed, int64_t episode_index) {
  Rng rng(derive_seed(seed, {tag(Stream::kGrasp), static_cast<uint64_t>(episode_index)}));
  GraspSetup s;
  s.grip_force_n = rng.int_in(kGripMinN, kGripMaxN);
  if (rng.bernoulli(kMissingFingerProb)) s.finger_in_contact[rng.int_in(0, kFingers - 1)] = false;
  for (int32_t f = 0; f < kFingers; ++f) {
    s.offset_x_mm[f] = rng.uniform(-kFingerOffsetMm, kFingerOffsetMm);
    s.offset_y_mm[f] = rng.uniform(-kFingerOffsetMm, kFingerOffsetMm);
  }
  sample_lift(rng, s.com_offset_mm, s.lift_accel_mps2);
  return s;
}

ObjectGeometry finger_geometry(const GraspObject& object, const GraspSetup& setup, int32_t f) {
  ObjectGeometry g = object.geometry;
  g.center_x_mm += setup.offset_x_mm[f];
  g.center_y_mm += setup.offset_y_mm[f];
  return g;
}

GraspVariables grasp_variables(const GraspObject& object, const GraspSetup& setup,
                               const GelContactModel& gel) {
  GraspVariables v;
  v.grip_force_n = setup.grip_force_n;
  v.friction = object.material.friction;
  for (int32_t f = 0; f < kFingers; ++f) {
    v.finger_in_contact[f] = setup.finger_in_contact[f];
    v.contact_area_mm2[f] = setup.finger_in_contact[f]
                                ? contact_area_mm2(gel, finger_geometry(object, setup, f),
                                                   object.mechanics, setup.grip_force_n)
                                : 0.0;
  }
  v.mass_kg = object.mass_kg;
  v.com_offset_mm = setup.com_offset_mm;
  v.lift_accel_mps2 = setup.lift_accel_mps2;
  v.slip_ratio = grasp_slip_ratio(v);
  v.margin = 1.0 - v.slip_ratio;
  return v;
}

}  // namespace internal

double grasp_slip_ratio(const GraspVariables& v) {
  const double q = v.mass_kg * (kGravity + v.lift_accel_mps2) / 2;   // N per finger
  const double torque = v.mass_kg * kGravity * v.com_offset_mm / 2;  // N mm per finger
  if (!(q > 0) && !(torque > 0)) return 0;                           // nothing to hold
  const double limit = v.friction * v.grip_force_n;                  // mu P
  double rho = 0;
  for (int32_t f = 0; f < kFingers; ++f) {
    if (!v.finger_in_contact[f]) continue;
    const double a = std::sqrt(std::max(v.contact_area_mm2[f], 0.0) / std::numbers::pi);
    const double torsion = 3.0 * std::numbers::pi / 16.0 * limit * a;
    const double rt = limit > 0 ? q / limit : (q > 0 ? kMaxSlipRatio : 0.0);
    const double rq = torsion > 0 ? torque / torsion : (torque > 0 ? kMaxSlipRatio : 0.0);
    rho = std::max(
        rho, std::min(std::sqrt(rt * rt + rq * rq), kMaxSlipRatio));  // both <= 1e6: no overflow
  }
  return std::isfinite(rho) ? rho : kMaxSlipRatio;
}

bool grasp_succeeds(const GraspVariables& v) {
  for (int32_t f = 0; f < kFingers; ++f) {
    if (!v.finger_in_contact[f]) return false;
  }
  if (v.mass_kg == 0) return true;  // nothing to hold
  if (!(v.grip_force_n > 0) || !(v.friction > 0)) return false;
  return grasp_slip_ratio(v) <= 1.0 / kGraspSafetyFactor;
}

}  // namespace tlvlink::sim
