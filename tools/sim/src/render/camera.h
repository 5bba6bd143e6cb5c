#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "camera.h is internal to tools/sim: include its public headers instead"
#endif
// The camera end of the pipeline (gelsight-sim.md step 7): the colour-change planes are blurred
// (5x5, sigma 1) where they are non-zero, added to the sensor's pre-blurred background, scaled by
// LED gain, channel gain and vignetting, and get Gaussian noise; then clamp and round to uint8.
// Optionally a JPEG round trip (one or more passes).

#include <array>
#include <cstddef>  // io/image.h uses size_t without including it
#include <cstdint>
#include <vector>

#include "render/sensor_tables.h"
#include "render/spreading.h"
#include "tlvlink/error.h"
#include "tlvlink/io/image.h"

namespace tlvlink::sim::internal {

struct ComposeParams {
  double led_gain = 1;
  double noise_sigma_dn = 0;
  uint64_t noise_seed = 0;
};

// out: height * width * 3 interleaved RGB. `delta` planes are read only inside `dirty`.
// `row_scratch` holds 7 * width floats.
void compose_frame(const SensorTables& tables, const std::array<const float*, 3>& delta, Roi dirty,
                   const ComposeParams& params, float* row_scratch, uint8_t* out);

// Encodes and decodes `rgb` `passes` times at `quality` (Feel frames were compressed twice).
// Allocates (libturbojpeg buffers); not part of the no-allocation guarantee.
Status jpeg_round_trip(std::vector<uint8_t>& rgb, int32_t width, int32_t height, int32_t quality,
                       int32_t passes, tools::Image& scratch);

}  // namespace tlvlink::sim::internal
