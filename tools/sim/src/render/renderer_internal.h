#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "renderer_internal.h is internal to tools/sim: include its public headers instead"
#endif
// A renderer that also draws the camera's field beyond the processed frame (the raw camera
// path, tools/sim/src/raw). Not part of the public API: its frames are larger than the profile
// says.

#include <cstdint>
#include <memory>

#include "render/sensor_tables.h"
#include "tlvlink/sim/renderer.h"

namespace tlvlink::sim::internal {

// Frames are (height + 2 periphery.y) x (width + 2 periphery.x) pixels at the profile's mm/px;
// profile() still reports the processed size. The centre matches Renderer::create's frame up to
// the camera noise (drawn row by row, so a wider row draws a different field), the texture and
// contact where they reach past the processed view (then the periphery takes load too), and
// edge handling of the camera blur. kHeightMap scenes need a map of the padded size.
// periphery {0, 0} is Renderer::create.
Result<std::unique_ptr<Renderer>> create_renderer_with_periphery(const SensorProfile& profile,
                                                                 uint64_t sensor_seed,
                                                                 Periphery periphery);

}  // namespace tlvlink::sim::internal
