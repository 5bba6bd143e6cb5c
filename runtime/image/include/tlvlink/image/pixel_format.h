#pragma once
// The pixel formats a camera delivers and tlvlink decodes, and the description of one frame's
// layout. Shared by capture (what the device negotiated) and image decoding (how to read it).

#include <cstddef>
#include <cstdint>

namespace tlvlink::image {

enum class PixelFormat : uint8_t {
  kMjpeg = 0,  // one baseline JPEG per frame; size varies per frame
  kYuyv = 1,   // YUYV 4:2:2 (Y0 U Y1 V per pixel pair), 2 bytes per pixel, even width
  kNv12 = 2,   // Y plane (width x height) then interleaved UV plane at half resolution
  kRgb24 = 3,  // interleaved 8-bit R, G, B
  kGrey = 4,   // 8-bit luma
};

// "mjpeg", "yuyv", "nv12", "rgb24", "grey".
const char* pixel_format_name(PixelFormat format);

// The V4L2 fourcc of a format (V4L2_PIX_FMT_*), and back; 0 / false for formats we do not read.
uint32_t pixel_format_fourcc(PixelFormat format);
bool pixel_format_from_fourcc(uint32_t fourcc, PixelFormat& format);

struct FrameFormat {
  PixelFormat format = PixelFormat::kRgb24;
  int32_t width = 0, height = 0;
  // Bytes per line of the first plane as the device delivers it (V4L2 bytesperline); 0 means
  // tightly packed. Unused for MJPEG.
  int32_t stride = 0;
};

// Bytes of one frame for the uncompressed formats (stride honoured); 0 for MJPEG.
size_t frame_bytes(const FrameFormat& format);

}  // namespace tlvlink::image
