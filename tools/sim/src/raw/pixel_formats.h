#pragma once
// Raw pixel formats and orientation: upright RGB (the processed frame's orientation) <-> the
// camera's RGB or YUYV bytes in the camera's orientation.
//
// YUYV 4:2:2 with BT.601 limited-range coefficients (what UVC webcams such as DIGIT send):
//   Y  = 16 + 219 (0.299 R + 0.587 G + 0.114 B) / 255            in [16, 235]
//   Cb = 128 + 224 (B - Y') / (1.772 * 255),  Cr = 128 + 224 (R - Y') / (1.402 * 255)
// (Y' = the unscaled luma) per pixel pair Y0 Cb Y1 Cr, the pair's chroma from the mean of its
// two pixels; decoding gives both pixels their pair's chroma (no interpolation, as libv4lconvert
// does) and the exact inverse matrix, clamped to [0, 255].

#include <cstddef>
#include <cstdint>

#include "raw/layout.h"

namespace tlvlink::sim::internal {

// Upright RGB (upright_size(layout)) <-> raw-orientation RGB (layout.width x layout.height).
void upright_to_raw_rgb(const uint8_t* upright, const RawLayout& layout, uint8_t* raw);
void raw_rgb_to_upright(const uint8_t* raw, const RawLayout& layout, uint8_t* upright);

// Upright RGB -> layout.width x layout.height YUYV (layout.width even), and back.
void upright_to_yuyv(const uint8_t* upright, const RawLayout& layout, uint8_t* yuyv);
void yuyv_to_upright(const uint8_t* yuyv, const RawLayout& layout, uint8_t* upright);

}  // namespace tlvlink::sim::internal
