#pragma once
// A camera frame -> the sensor's processed RGB frame (the frame its models were trained on):
// decode (MJPEG at a DCT scale, or YUYV / NV12 / RGB24 / GREY), turn upright, cut the view out of
// the camera's field and resample it to the processed size. Made once per camera format
// (allocates); decode() allocates nothing.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/image/convert.h"
#include "tlvlink/image/image.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/image/pixel_format.h"
#include "tlvlink/image/resample.h"

namespace tlvlink::image {

// Where the sensor's processed frame lies in what its camera emits.
struct SensorView {
  int32_t width = 0, height = 0;  // the processed (upright) frame, e.g. 320x240
  double crop = 0;                // fraction of each camera border outside the view, [0, 0.5)
  Orientation orientation = Orientation::kUpright;
  // MJPEG: decode at 1/1, 1/2, 1/4 or 1/8. 0 = the smallest scale whose cropped view keeps at
  // least kMinViewShare of the processed size on each axis (1/8 for a GelSight Mini's
  // 3280x2464 into 320x240, 1/1 for 320x240 MJPEG).
  int32_t jpeg_scale_denominator = 0;
};
inline constexpr double kMinViewShare = 0.8;
// The camera frame (upright, cropped) and the view may differ in aspect by this much: a row or
// two of a cropped frame. More would stretch the gel, so create() refuses it naming both sizes.
inline constexpr double kMaxViewAspectChange = 0.02;

namespace internal {
class JpegRegionDecoder;
}

// MJPEG with a crop (a GelSight Mini) decodes only the view and a 2-px margin for the resampler:
// rows outside it are only entropy-decoded, columns outside it not transformed. That is the
// entropy-decoding floor; a whole-frame decode at the same scale costs ~16 % more.
class FrameDecoder {
 public:
  // `camera` is what the device delivers. Errors: a view that does not fit, an unsupported scale.
  static Result<FrameDecoder> create(const FrameFormat& camera, const SensorView& view);
  FrameDecoder();
  FrameDecoder(FrameDecoder&&) noexcept;
  FrameDecoder& operator=(FrameDecoder&&) noexcept;
  ~FrameDecoder();

  // The camera frame -> `out`, exactly view.width * view.height * 3 bytes of upright RGB.
  // A frame of the wrong size or format, or a truncated or corrupt JPEG, is a kFormat error that
  // says what was expected; `what` names the stream ("mini-left frame").
  Status decode(std::span<const uint8_t> frame, std::span<uint8_t> out, const char* what);

  const FrameFormat& camera() const { return camera_; }
  const SensorView& view() const { return view_; }
  int32_t jpeg_scale_denominator() const { return scale_; }  // 1 unless MJPEG
  size_t output_bytes() const;

 private:
  FrameFormat camera_;
  SensorView view_;
  int32_t scale_ = 1;
  FrameFormat decoded_;  // camera_ at the decode scale, packed RGB24
  bool resize_ = false;
  JpegDecoder jpeg_;
  std::unique_ptr<internal::JpegRegionDecoder> region_;  // MJPEG with a crop, upright
  int32_t planned_region_x_ = -1;     // the region's first column the resampler was planned for
  std::vector<uint8_t> decoded_rgb_;  // MJPEG at scale, camera orientation
  std::vector<uint8_t> upright_;
  Resampler resampler_;
};

}  // namespace tlvlink::image
