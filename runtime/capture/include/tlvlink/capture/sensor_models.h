#pragma once
// The tactile sensors tlvlink knows: how each one's camera shows up (USB ids, the format it
// streams) and where its processed frame lies in what the camera emits. A daemon configured with
// `model = "gelsight-mini"` gets all of it; the simulator renders exactly these cameras (a test
// checks that its profiles agree with this table).

#include <cstdint>
#include <span>
#include <string_view>

#include "tlvlink/image/frame_decoder.h"
#include "tlvlink/image/pixel_format.h"

namespace tlvlink::capture {

struct SensorModel {
  std::string_view name;
  uint16_t usb_vendor = 0, usb_product = 0;  // 0: not a USB camera
  image::PixelFormat format = image::PixelFormat::kMjpeg;
  int32_t width = 0, height = 0;  // what the camera streams
  double fps = 0;
  image::SensorView view;      // the processed frame and how it is cut from the camera's
  uint32_t warmup_frames = 0;  // frames to discard after each open
  std::string_view notes;
};

// gelsight-mini, gelsight-mini-processed, digit, digit-640x480, gelsight-r1.5.
std::span<const SensorModel> sensor_models();
const SensorModel* find_sensor_model(std::string_view name);  // nullptr when unknown

}  // namespace tlvlink::capture
