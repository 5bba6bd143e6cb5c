// Image files as a sensor's processed view (sensor_frame.h).

#include "tlvlink/io/sensor_frame.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "tlvlink/capture/still_frame.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/model_input.h"

namespace tlvlink::tools {
namespace {

// A frame of no known size is taken as it is when its aspect is within this of a 4:3 view (either
// way round): every known sensor's view is 4:3, and 2 % is a row or two of a cropped frame.
constexpr double kAspectTolerance = 0.02;

std::string sizes_of_sensors() {
  std::string s;
  for (const capture::SensorModel& m : capture::sensor_models()) {
    char one[128];
    std::snprintf(one, sizeof(one), "%s%.*s: camera %dx%d, view %dx%d", s.empty() ? "" : "; ",
                  static_cast<int>(m.name.size()), m.name.data(), m.width, m.height, m.view.width,
                  m.view.height);
    s += one;
  }
  return s;
}

std::span<const uint8_t> as_u8(std::span<const std::byte> b) {
  return {reinterpret_cast<const uint8_t*>(b.data()), b.size()};
}

Result<SensorFrame> as_sensor(std::span<const std::byte> bytes, const std::string& name,
                              const capture::SensorModel& s, const Image* decoded) {
  SensorFrame f;
  f.sensor = std::string(s.name);
  if (sniff_input_file(bytes) == InputFileKind::kJpeg) {
    TLV_ASSIGN_OR_RETURN(f.view, capture::view_from_still_jpeg(as_u8(bytes), s, name));
  } else {
    TLV_ASSIGN_OR_RETURN(const Image image,
                         decoded ? Result<Image>(*decoded) : decode_image_file(bytes, name));
    TLV_ASSIGN_OR_RETURN(f.view, capture::view_from_still_rgb(image.view(), s, name));
  }
  return f;
}

}  // namespace

std::string known_sensor_names() {
  std::string s;
  for (const capture::SensorModel& m : capture::sensor_models()) {
    s += (s.empty() ? "" : ", ") + std::string(m.name);
  }
  return s;
}

Result<SensorFrame> sensor_frame_from_bytes(std::span<const std::byte> bytes,
                                            const std::string& name, std::string_view sensor) {
  if (!sensor.empty()) {
    const capture::SensorModel* s = capture::find_sensor_model(sensor);
    TLV_ENSURE(s != nullptr, ErrorCode::kInvalidArgument, "unknown sensor '%.*s' (known: %s)",
               static_cast<int>(sensor.size()), sensor.data(), known_sensor_names().c_str());
    auto f = as_sensor(bytes, name, *s, nullptr);
    if (!f.ok()) return f.error().with_context("%s", name.c_str());
    return f;
  }
  TLV_ASSIGN_OR_RETURN(Image image, decode_image_file(bytes, name));
  const std::vector<const capture::SensorModel*> candidates =
      capture::sensors_of_size(image.width, image.height);
  // A camera frame of exactly one sensor is cut to that sensor's view; a frame at a view's size
  // (what SDKs hand users) is taken as it is, whichever sensor it came from.
  const capture::SensorModel* camera_of = nullptr;
  int cameras = 0;
  bool is_view = false;
  for (const capture::SensorModel* s : candidates) {
    if (capture::classify_still(*s, image.width, image.height).value() ==
        capture::StillKind::kCameraFrame) {
      camera_of = s;
      ++cameras;
    } else {
      is_view = true;
    }
  }
  SensorFrame f;
  char note[256];
  if (!is_view && cameras == 1) {
    TLV_ASSIGN_OR_RETURN(f, as_sensor(bytes, name, *camera_of, &image));
    std::snprintf(note, sizeof(note),
                  "%s: a %dx%d %s camera frame, cut to its %dx%d view as tlvlinkd cuts it",
                  name.c_str(), image.width, image.height, f.sensor.c_str(), f.view.width,
                  f.view.height);
    f.note = note;
    return f;
  }
  if (is_view) {
    f.view = std::move(image);
    return f;
  }
  const double aspect = static_cast<double>(image.width) / image.height;
  const bool four_three = std::abs(aspect / (4.0 / 3.0) - 1) <= kAspectTolerance ||
                          std::abs(aspect / (3.0 / 4.0) - 1) <= kAspectTolerance;
  TLV_ENSURE(four_three, ErrorCode::kShapeMismatch,
             "%s: a %dx%d frame (aspect %.3f) is no known sensor's camera frame or view and not "
             "4:3 within %.0f %%; resizing it would distort the gel (known: %s); crop it to the "
             "sensor's view, or pass --sensor",
             name.c_str(), image.width, image.height, aspect, 100 * kAspectTolerance,
             sizes_of_sensors().c_str());
  std::snprintf(note, sizeof(note),
                "%s: a %dx%d frame of no known sensor, taken as a processed view", name.c_str(),
                image.width, image.height);
  f.view = std::move(image);
  f.note = note;
  return f;
}

Result<SensorFrame> sensor_frame_from_file(const std::string& path, std::string_view sensor) {
  TLV_ASSIGN_OR_RETURN(std::vector<std::byte> bytes, read_file(path, kMaxSensorFrameFileBytes));
  return sensor_frame_from_bytes(bytes, path, sensor);
}

std::vector<std::string> trained_sensors(const Model& model) {
  std::vector<std::string> out;
  const std::string_view text = model.metadata().provenance.training;
  const nlohmann::json j = nlohmann::json::parse(text.begin(), text.end(), nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("dataset")) return out;
  const nlohmann::json& d = j["dataset"];
  if (!d.is_object() || !d.contains("sensors") || !d["sensors"].is_array()) return out;
  for (const nlohmann::json& s : d["sensors"])
    if (s.is_string()) out.push_back(s.get<std::string>());
  std::sort(out.begin(), out.end());
  return out;
}

Status check_trained_sensor(const Model& model, const SensorFrame& frame, const std::string& name) {
  if (frame.sensor.empty()) return {};
  const std::vector<std::string> sensors = trained_sensors(model);
  if (sensors.empty() || std::find(sensors.begin(), sensors.end(), frame.sensor) != sensors.end()) {
    return {};
  }
  std::string list;
  for (const std::string& s : sensors) list += (list.empty() ? "" : ", ") + s;
  return Error::make(ErrorCode::kShapeMismatch,
                     "%s: a %s frame, and the model was trained on %s frames only: its view, "
                     "colours and scale are not what the model learnt (fit heads on your own "
                     "frames, or use a model trained for %s)",
                     name.c_str(), frame.sensor.c_str(), list.c_str(), frame.sensor.c_str());
}

}  // namespace tlvlink::tools
