#include "tlvlink/image/pixel_format.h"

#include <linux/videodev2.h>

#include <initializer_list>

namespace tlvlink::image {

const char* pixel_format_name(PixelFormat format) {
  switch (format) {
    case PixelFormat::kMjpeg: return "mjpeg";
    case PixelFormat::kYuyv: return "yuyv";
    case PixelFormat::kNv12: return "nv12";
    case PixelFormat::kRgb24: return "rgb24";
    case PixelFormat::kGrey: return "grey";
  }
  return "unknown";
}

uint32_t pixel_format_fourcc(PixelFormat format) {
  switch (format) {
    case PixelFormat::kMjpeg: return V4L2_PIX_FMT_MJPEG;
    case PixelFormat::kYuyv: return V4L2_PIX_FMT_YUYV;
    case PixelFormat::kNv12: return V4L2_PIX_FMT_NV12;
    case PixelFormat::kRgb24: return V4L2_PIX_FMT_RGB24;
    case PixelFormat::kGrey: return V4L2_PIX_FMT_GREY;
  }
  return 0;
}

bool pixel_format_from_fourcc(uint32_t fourcc, PixelFormat& format) {
  for (PixelFormat f : {PixelFormat::kMjpeg, PixelFormat::kYuyv, PixelFormat::kNv12,
                        PixelFormat::kRgb24, PixelFormat::kGrey}) {
    if (pixel_format_fourcc(f) == fourcc) {
      format = f;
      return true;
    }
  }
  return false;
}

size_t frame_bytes(const FrameFormat& f) {
  if (f.width <= 0 || f.height <= 0) return 0;
  const auto w = static_cast<size_t>(f.width), h = static_cast<size_t>(f.height);
  const auto line = [&](size_t packed) {
    return f.stride > 0 ? static_cast<size_t>(f.stride) : packed;
  };
  switch (f.format) {
    case PixelFormat::kMjpeg: return 0;
    case PixelFormat::kYuyv: return line(w * 2) * h;
    case PixelFormat::kNv12: return line(w) * h + line(w) * ((h + 1) / 2);
    case PixelFormat::kRgb24: return line(w * 3) * h;
    case PixelFormat::kGrey: return line(w) * h;
  }
  return 0;
}

}  // namespace tlvlink::image
