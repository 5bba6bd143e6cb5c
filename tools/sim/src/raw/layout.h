#pragma once
// Raw-frame geometry shared by RawCamera and RawDecoder: how a processed pixel maps into the
// raw frame and how wide a periphery the renderer must draw to fill it.

#include <cstdint>

#include "render/sensor_tables.h"
#include "tlvlink/sim/raw_camera.h"

namespace tlvlink::sim::internal {

// An axis map for the resampler: destination pixel i (centre i + 0.5) reads the source at the
// continuous coordinate offset + (i + 0.5) * scale (pixel edges at integers).
struct AxisMap {
  double offset = 0, scale = 1;
};

// The raw frame in the processed frame's orientation ("upright raw"): width x height swapped
// back when the layout is transposed.
struct UprightSize {
  int32_t width = 0, height = 0;
};
UprightSize upright_size(const RawLayout& layout);

// Periphery (px at the processed scale) that covers the raw view beyond the processed frame,
// plus 2 px for the resampler's support and rounding.
Periphery raw_periphery(const RawLayout& layout, const SensorProfile& profile);

// Rendering: an upright raw axis of `raw_len` pixels reads the rendered axis of
// `processed_len + 2 pad` pixels (processed frame at [pad, pad + processed_len)).
AxisMap raw_from_render(double crop, int32_t raw_len, int32_t processed_len, int32_t pad);
// Recovery: a processed axis of `processed_len` pixels reads a decoded upright raw axis of
// `decoded_len` pixels, cut by `crop` on each side.
AxisMap processed_from_raw(double crop, int32_t decoded_len, int32_t processed_len);

}  // namespace tlvlink::sim::internal
