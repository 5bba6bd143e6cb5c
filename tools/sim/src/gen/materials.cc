// Sampling one object of a material class (the class table is tools/touch's).

#include <algorithm>
#include <cmath>

#include "gen/rng.h"
#include "tlvlink/sim/materials.h"

namespace tlvlink::sim {

Result<MaterialSample> sample_material(int32_t class_id, uint64_t seed) {
  TLV_ASSIGN_OR_RETURN(const MaterialClass* c, material_class(class_id));
  internal::Rng rng(internal::derive_seed(
      seed, {internal::tag(internal::Stream::kMaterial), static_cast<uint64_t>(class_id)}));
  MaterialSample m;
  m.class_id = class_id;
  m.modulus_pa = rng.log_uniform(c->modulus_pa.lo, c->modulus_pa.hi);
  m.poisson = rng.uniform(c->poisson.lo, c->poisson.hi);
  m.friction = rng.uniform(c->friction.lo, c->friction.hi);
  m.sq_um = rng.log_uniform(c->sq_um.lo, c->sq_um.hi);
  m.correlation_length_mm = rng.uniform(c->correlation_length_mm.lo, c->correlation_length_mm.hi);
  m.hurst = rng.uniform(c->hurst.lo, c->hurst.hi);
  m.layer_mm = c->layer_mm.hi > 0 ? rng.log_uniform(c->layer_mm.lo, c->layer_mm.hi) : 0.0;
  m.hard = hard_label(m.modulus_pa);
  m.rough = rough_label(m.sq_um);
  // Half the jitter is shared by the channels (lighter/darker object), half per channel (hue).
  const double shade = rng.uniform(-0.5, 0.5) * c->colour_jitter;
  for (size_t k = 0; k < 3; ++k) {
    const double v = c->colour[k] + shade + rng.uniform(-0.5, 0.5) * c->colour_jitter;
    m.colour[k] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  }
  return m;
}

}  // namespace tlvlink::sim
