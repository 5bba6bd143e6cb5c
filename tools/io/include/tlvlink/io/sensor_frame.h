#pragma once
// An image file as a tactile sensor's processed view, the frame a model reads (runtime/capture
// still_frame.h does the cutting with the board's decoder). The sensor is named, or detected
// from the frame's size: a GelSight Mini's 3280x2464 camera frame is cut to its 320x240 view
// exactly as tlvlinkd cuts it, a frame at a known view's size is taken as it is, and a frame of
// any other size is an error that names the sizes the sensors produce (resizing it would change
// the gel's scale or aspect the model learned).
//
//   auto f = tools::sensor_frame_from_bytes(bytes, "frame.jpg", "");   // detect
//   // f->view: the processed frame; f->note: what was done ("gelsight-mini camera frame ...")

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/io/image.h"
#include "tlvlink/model.h"

namespace tlvlink::tools {

struct SensorFrame {
  Image view;
  std::string
      sensor;  // the sensor it was read as; empty: no known sensor (a 4:3 frame taken as it is)
  std::string note;  // one line on what was done, for the user
};

// `sensor`: a known sensor name (runtime/capture sensor_models.h), or empty to detect. Errors:
// an unknown sensor name (kInvalidArgument, listing the known ones), a frame the sensor (or any
// known sensor) cannot have produced (kShapeMismatch, naming the sizes), decoding errors.
Result<SensorFrame> sensor_frame_from_bytes(std::span<const std::byte> bytes,
                                            const std::string& name, std::string_view sensor);

// The same for a frame file (PNG, JPEG, PPM), read only when a regular file of at most
// kMaxSensorFrameFileBytes (checked before reading; a camera frame's file is far smaller).
inline constexpr size_t kMaxSensorFrameFileBytes = size_t{64} << 20;
Result<SensorFrame> sensor_frame_from_file(const std::string& path, std::string_view sensor);

// The known sensor names, comma-separated (for help texts and errors).
std::string known_sensor_names();

// The sensors whose frames the model was trained on, as its provenance records them
// (training.dataset.sensors; sorted); empty when it records none (ONNX imports, older files).
std::vector<std::string> trained_sensors(const Model& model);

// `frame` (read as `frame.sensor`) is one the model was trained for: kShapeMismatch naming both
// otherwise. A model that records no sensors, or a frame of no known sensor, passes.
Status check_trained_sensor(const Model& model, const SensorFrame& frame, const std::string& name);

}  // namespace tlvlink::tools
