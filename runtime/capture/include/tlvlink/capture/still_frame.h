#pragma once
// A still frame as a user holds it — a file the sensor's SDK saved, or one camera frame stored
// as it came — turned into the sensor's processed view by the board's own decoder
// (image::FrameDecoder), so a host tool shows the model what tlvlinkd would. A GelSight Mini's
// 3280x2464 camera JPEG is decoded at 1/8 and cropped 15 % per border exactly as the daemon
// decodes it; a frame already at the view's size is taken as it is; any other size is an error
// that names the sizes the sensor produces.
//
//   const capture::SensorModel* mini = capture::find_sensor_model("gelsight-mini");
//   auto view = capture::view_from_still_jpeg(file_bytes, *mini);   // 320x240 RGB

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/capture/sensor_models.h"
#include "tlvlink/error.h"
#include "tlvlink/image/image.h"

namespace tlvlink::capture {

enum class StillKind : uint8_t {
  kCameraFrame = 0,    // what the camera emits (its size and orientation)
  kProcessedView = 1,  // the sensor's processed, upright frame (what its SDK hands users)
};
const char* still_kind_name(StillKind kind);  // "camera frame", "processed view"

// What a width x height frame is to `sensor`; kShapeMismatch naming both sizes it accepts.
Result<StillKind> classify_still(const SensorModel& sensor, int32_t width, int32_t height);

// The known sensors whose camera frame or processed view has this size (for detection; the
// caller decides what to do with none or several).
std::vector<const SensorModel*> sensors_of_size(int32_t width, int32_t height);

// The processed view of a still JPEG: a camera frame of an MJPEG sensor through FrameDecoder
// (DCT scale, crop, resampling: the daemon's bytes), or an already processed view, decoded.
// `what` names the file in errors.
Result<image::Image> view_from_still_jpeg(std::span<const uint8_t> jpeg, const SensorModel& sensor,
                                          const std::string& what);
// The same from decoded RGB pixels (PNG, PPM, or a JPEG of an uncompressed camera's frame): a
// camera frame goes through FrameDecoder as RGB24 in the camera's orientation.
Result<image::Image> view_from_still_rgb(const image::ImageView& rgb, const SensorModel& sensor,
                                         const std::string& what);

}  // namespace tlvlink::capture
