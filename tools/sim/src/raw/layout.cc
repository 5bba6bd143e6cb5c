// RawLayout from a profile, and the coordinate maps between raw and processed frames.
#include "raw/layout.h"

#include <cmath>

namespace tlvlink::sim {

const char* raw_format_name(RawFormat format) {
  switch (format) {
    case RawFormat::kRgb: return "rgb";
    case RawFormat::kMjpeg: return "mjpeg";
    case RawFormat::kYuyv: return "yuyv";
  }
  return "?";
}

Result<RawLayout> raw_layout(const SensorProfile& p) {
  TLV_TRY(validate(p));
  RawLayout l;
  l.format = p.raw_format == "mjpeg"  ? RawFormat::kMjpeg
             : p.raw_format == "yuyv" ? RawFormat::kYuyv
                                      : RawFormat::kRgb;
  l.crop = p.raw_crop;
  l.transposed = p.raw_transposed;
  if (p.raw_width != 0) {
    l.width = p.raw_width;
    l.height = p.raw_height;
  } else {  // the processed size, in the camera's orientation
    l.width = l.transposed ? p.height : p.width;
    l.height = l.transposed ? p.width : p.height;
  }
  const internal::UprightSize up = internal::upright_size(l);
  // The crop cuts the same fraction from each axis, so the aspect ratio is the raw frame's.
  const double raw_aspect = static_cast<double>(up.width) / up.height;
  const double aspect = static_cast<double>(p.width) / p.height;
  TLV_ENSURE(std::fabs(raw_aspect / aspect - 1) <= 0.02, ErrorCode::kInvalidArgument,
             "sensor %.*s: raw %dx%d%s has aspect %.4f, the processed %dx%d has %.4f (> 2 %% off)",
             static_cast<int>(p.name.size()), p.name.data(), l.width, l.height,
             l.transposed ? " (transposed)" : "", raw_aspect, p.width, p.height, aspect);
  TLV_ENSURE(l.format != RawFormat::kYuyv || l.width % 2 == 0, ErrorCode::kInvalidArgument,
             "sensor %.*s: YUYV needs an even raw width (pixel pairs share U and V), got %d",
             static_cast<int>(p.name.size()), p.name.data(), l.width);
  const size_t pixels = static_cast<size_t>(l.width) * static_cast<size_t>(l.height);
  l.frame_bytes = l.format == RawFormat::kRgb    ? pixels * 3
                  : l.format == RawFormat::kYuyv ? pixels * 2
                                                 : 0;
  return l;
}

namespace internal {

UprightSize upright_size(const RawLayout& l) {
  return image::upright_size(l.width, l.height, orientation(l));
}

image::FrameFormat camera_format(const RawLayout& l) {
  const image::PixelFormat f = l.format == RawFormat::kMjpeg  ? image::PixelFormat::kMjpeg
                               : l.format == RawFormat::kYuyv ? image::PixelFormat::kYuyv
                                                              : image::PixelFormat::kRgb24;
  return {f, l.width, l.height, 0};
}

image::Orientation orientation(const RawLayout& l) {
  return l.transposed ? image::Orientation::kTransposed : image::Orientation::kUpright;
}

Periphery raw_periphery(const RawLayout& l, const SensorProfile& p) {
  if (l.crop <= 0) return {};
  // The raw view spans processed_len / (1 - 2 crop): crop / (1 - 2 crop) of it on each side.
  const double side = l.crop / (1 - 2 * l.crop);
  auto pad = [side](int32_t len) { return static_cast<int32_t>(std::ceil(side * len)) + 2; };
  return {pad(p.width), pad(p.height)};
}

AxisMap raw_from_render(double crop, int32_t raw_len, int32_t processed_len, int32_t pad) {
  // Raw coordinate r (edges at integers) is processed coordinate
  // (r - crop raw_len) * processed_len / ((1 - 2 crop) raw_len), shifted by pad into the render.
  const double scale = processed_len / ((1 - 2 * crop) * raw_len);
  return {pad - crop * raw_len * scale, scale};
}

}  // namespace internal
}  // namespace tlvlink::sim
