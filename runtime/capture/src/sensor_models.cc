#include "tlvlink/capture/sensor_models.h"

#include <array>

namespace tlvlink::capture {
namespace {

using image::Orientation;
using image::PixelFormat;

constexpr std::array<SensorModel, 5> kModels = {{
    // MJPEG 3280x2464 at 25 fps is the only mode the camera offers (a smaller size is silently
    // ignored); the gsrobotics SDK crops 15 % of each border and resizes to 320x240. The first
    // frames after open are black.
    {"gelsight-mini",
     0x0c45,
     0x636d,
     PixelFormat::kMjpeg,
     3280,
     2464,
     25.0,
     {320, 240, 0.15, Orientation::kUpright, 0},
     5,
     "Arducam UVC camera; a metadata node beside the capture node"},
    // What the gsrobotics SDK hands users: Mini frames already cropped and resized to 320x240
    // (its saved images and recordings, a re-streamed view). Taken whole: cropping 15 % again
    // would cut the gel.
    {"gelsight-mini-processed",
     0,
     0,
     PixelFormat::kMjpeg,
     320,
     240,
     25.0,
     {320, 240, 0.0, Orientation::kUpright, 1},
     0,
     "GelSight Mini frames already processed by the gsrobotics SDK (320x240, no crop)"},
    // DIGIT: 320x240 YUYV at 60 fps (or 30); frames are transposed and flipped top to bottom
    // into a 240-wide, 320-high portrait frame, as digit-interface returns them.
    {"digit",
     0x2833,
     0x0209,
     PixelFormat::kYuyv,
     320,
     240,
     60.0,
     {240, 320, 0.0, Orientation::kTransposed, 0},
     0,
     "LEDs through the UVC zoom control; needs a USB 2.0 data cable"},
    {"digit-640x480",
     0x2833,
     0x0209,
     PixelFormat::kYuyv,
     640,
     480,
     30.0,
     {480, 640, 0.0, Orientation::kTransposed, 0},
     0,
     "DIGIT at VGA, 30 fps"},
    // R1.5: 320x240 MJPEG from its internal Pi (an HTTP stream, not a USB camera).
    {"gelsight-r1.5",
     0,
     0,
     PixelFormat::kMjpeg,
     320,
     240,
     60.0,
     {320, 240, 0.0, Orientation::kUpright, 1},
     0,
     "older research sensor"},
}};

}  // namespace

std::span<const SensorModel> sensor_models() { return kModels; }

const SensorModel* find_sensor_model(std::string_view name) {
  for (const SensorModel& m : kModels)
    if (m.name == name) return &m;
  return nullptr;
}

}  // namespace tlvlink::capture
