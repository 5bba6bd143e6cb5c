#pragma once
// Uncompressed camera pixels <-> upright RGB. "Upright" is the sensor's own orientation, the one
// its processed frames and models use; some cameras deliver it turned (DIGIT sends frames
// transposed: upright = flip_top_bottom(transpose(camera))).
//
// YUYV and NV12 use BT.601 limited-range coefficients (what UVC webcams such as DIGIT send):
//   Y  = 16 + 219 (0.299 R + 0.587 G + 0.114 B) / 255            in [16, 235]
//   Cb = 128 + 224 (B - Y') / (1.772 * 255),  Cr = 128 + 224 (R - Y') / (1.402 * 255)
// Decoding gives every pixel its pair's (YUYV) or 2x2 block's (NV12) chroma, no interpolation
// (as libv4lconvert does), through the exact inverse matrix, clamped to [0, 255]. GREY is
// replicated into R, G and B.

#include <cstddef>
#include <cstdint>
#include <span>

#include "tlvlink/error.h"
#include "tlvlink/image/pixel_format.h"

namespace tlvlink::image {

enum class Orientation : uint8_t {
  kUpright = 0,
  kTransposed = 1,  // upright = flip_top_bottom(transpose(camera)), DIGIT's
};

// The upright size of a camera frame of width x height.
struct Size {
  int32_t width = 0, height = 0;
};
Size upright_size(int32_t camera_width, int32_t camera_height, Orientation orientation);

// One uncompressed frame (YUYV, NV12, RGB24 or GREY, `format.stride` honoured) -> upright RGB,
// packed, upright_size(...) pixels. `frame` must hold frame_bytes(format) (kFormat otherwise,
// naming `what`), `upright` exactly width * height * 3 bytes. No allocation.
Status camera_to_upright_rgb(std::span<const uint8_t> frame, const FrameFormat& format,
                             Orientation orientation, std::span<uint8_t> upright, const char* what);

// The inverse, for simulated cameras: upright RGB -> the camera's RGB24 or YUYV in its own
// orientation (format.width even for YUYV), packed.
Status upright_rgb_to_camera(std::span<const uint8_t> upright, const FrameFormat& format,
                             Orientation orientation, std::span<uint8_t> frame);

}  // namespace tlvlink::image
