#pragma once
#ifndef TLVLINK_SIM_PRIVATE
#error "layout.h is internal to tools/sim: include its public headers instead"
#endif
// Raw-frame geometry shared by RawCamera and RawDecoder: how a processed pixel maps into the
// raw frame and how wide a periphery the renderer must draw to fill it.

#include <cstdint>

#include "render/sensor_tables.h"
#include "tlvlink/image/convert.h"
#include "tlvlink/image/pixel_format.h"
#include "tlvlink/image/resample.h"
#include "tlvlink/sim/raw_camera.h"

namespace tlvlink::sim::internal {

using image::AxisMap;

// The raw frame in the processed frame's orientation ("upright raw"): width x height swapped
// back when the layout is transposed.
using UprightSize = image::Size;
UprightSize upright_size(const RawLayout& layout);

// The layout as the runtime's image component describes a camera frame and its orientation.
image::FrameFormat camera_format(const RawLayout& layout);
image::Orientation orientation(const RawLayout& layout);

// Periphery (px at the processed scale) that covers the raw view beyond the processed frame,
// plus 2 px for the resampler's support and rounding.
Periphery raw_periphery(const RawLayout& layout, const SensorProfile& profile);

// Rendering: an upright raw axis of `raw_len` pixels reads the rendered axis of
// `processed_len + 2 pad` pixels (processed frame at [pad, pad + processed_len)).
AxisMap raw_from_render(double crop, int32_t raw_len, int32_t processed_len, int32_t pad);

}  // namespace tlvlink::sim::internal
