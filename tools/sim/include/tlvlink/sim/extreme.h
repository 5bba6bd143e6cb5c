#pragma once
// The extreme set (issue 3 item 7): named scenes at the edges of the parameter space that every
// consumer must survive — the renderer's tests, the runtime's stability suite and the
// quantizer's calibration. Each must render to a finite uint8 frame of the profile's size with
// finite ContactState. Plus the parameter sets that must be rejected (NaN/Inf and out-of-range
// values), each naming the field the error has to mention. Lists: tools/sim/REFERENCE.md.

#include <span>
#include <string>
#include <string_view>

#include "tlvlink/error.h"
#include "tlvlink/sim/renderer.h"
#include "tlvlink/sim/scene.h"
#include "tlvlink/sim/sensor.h"

namespace tlvlink::sim {

struct ExtremeCase {
  std::string_view name;  // stable, e.g. "no-contact", "object-1e12pa", "jpeg-q1"
  std::string_view what;  // what it stresses, one line
  SensorProfile sensor;   // a built-in profile, possibly with a modified gel
  ContactScene scene;
  RenderOptions options;
};

// Built once, thread-safe; stable order.
std::span<const ExtremeCase> extreme_cases();
// nullptr if there is no case of that name.
const ExtremeCase* find_extreme_case(std::string_view name);

struct InvalidCase {
  std::string name;        // e.g. "nan:scene.loading.force_n"
  std::string_view field;  // the field the error message must name
  SensorProfile sensor;    // exactly one of sensor / scene / options is invalid
  ContactScene scene;
  RenderOptions options;
};

std::span<const InvalidCase> invalid_parameter_cases();

// validate(sensor), then validate(scene), then validate(options): the first error.
Status validate_all(const SensorProfile& sensor, const ContactScene& scene,
                    const RenderOptions& options);

}  // namespace tlvlink::sim
