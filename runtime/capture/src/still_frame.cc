// Still frames into the sensor's processed view through the board's decoder.

#include "tlvlink/capture/still_frame.h"

#include <cstring>

#include "tlvlink/image/frame_decoder.h"
#include "tlvlink/image/jpeg.h"

namespace tlvlink::capture {
namespace {

Result<image::Image> decode_with(const image::FrameFormat& format, const SensorModel& sensor,
                                 std::span<const uint8_t> bytes, const std::string& what) {
  TLV_ASSIGN_OR_RETURN(image::FrameDecoder decoder,
                       image::FrameDecoder::create(format, sensor.view));
  image::Image out{sensor.view.width, sensor.view.height, 3, {}};
  out.pixels.resize(decoder.output_bytes());
  TLV_TRY(decoder.decode(bytes, out.pixels, what.c_str()));
  return out;
}

}  // namespace

const char* still_kind_name(StillKind kind) {
  return kind == StillKind::kCameraFrame ? "camera frame" : "processed view";
}

Result<StillKind> classify_still(const SensorModel& s, int32_t width, int32_t height) {
  if (width == s.view.width && height == s.view.height) return StillKind::kProcessedView;
  if (width == s.width && height == s.height) return StillKind::kCameraFrame;
  return Error::make(
      ErrorCode::kShapeMismatch,
      "a %dx%d frame is neither a %.*s camera frame (%dx%d) nor its processed view "
      "(%dx%d); resizing it would change the gel's scale or aspect the model learned",
      width, height, static_cast<int>(s.name.size()), s.name.data(), s.width, s.height,
      s.view.width, s.view.height);
}

std::vector<const SensorModel*> sensors_of_size(int32_t width, int32_t height) {
  std::vector<const SensorModel*> found;
  for (const SensorModel& s : sensor_models()) {
    if (classify_still(s, width, height).ok()) found.push_back(&s);
  }
  return found;
}

Result<image::Image> view_from_still_jpeg(std::span<const uint8_t> jpeg, const SensorModel& s,
                                          const std::string& what) {
  image::JpegDecoder header_reader;
  TLV_ASSIGN_OR_RETURN(const image::JpegHeader h, header_reader.read_header(jpeg, what.c_str()));
  TLV_ASSIGN_OR_RETURN(const StillKind kind, classify_still(s, h.width, h.height));
  if (kind == StillKind::kCameraFrame && s.format == image::PixelFormat::kMjpeg) {
    return decode_with({image::PixelFormat::kMjpeg, s.width, s.height, 0}, s, jpeg, what);
  }
  TLV_ASSIGN_OR_RETURN(image::Image rgb, image::decode_jpeg(jpeg, what));
  if (kind == StillKind::kProcessedView) return rgb;
  return view_from_still_rgb(rgb.view(), s, what);
}

Result<image::Image> view_from_still_rgb(const image::ImageView& rgb, const SensorModel& s,
                                         const std::string& what) {
  TLV_ENSURE(rgb.channels == 3, ErrorCode::kFormat, "%s: %d channels, a camera frame is RGB",
             what.c_str(), rgb.channels);
  TLV_ASSIGN_OR_RETURN(const StillKind kind, classify_still(s, rgb.width, rgb.height));
  std::vector<uint8_t> packed(static_cast<size_t>(rgb.width) * static_cast<size_t>(rgb.height) * 3);
  for (int32_t y = 0; y < rgb.height; ++y) {
    std::memcpy(packed.data() + static_cast<size_t>(y) * static_cast<size_t>(rgb.width) * 3,
                rgb.row(y), static_cast<size_t>(rgb.width) * 3);
  }
  if (kind == StillKind::kProcessedView)
    return image::Image{rgb.width, rgb.height, 3, std::move(packed)};
  return decode_with({image::PixelFormat::kRgb24, s.width, s.height, 0}, s, packed, what);
}

}  // namespace tlvlink::capture
