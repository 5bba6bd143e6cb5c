#pragma once
// Recorded camera frames for the pipeline benchmarks: the simulated sensor's raw output (a Mini's
// MJPEG 3280x2464, DIGIT's YUYV) of presses at varied places, forces and textures, one in five
// without contact, written as DIR/frame_NNNN.jpg or .yuyv.

#include <string>

#include "tlvlink/error.h"

namespace tlvlink::bench {

Status make_frames(const std::string& sensor, const std::string& dir, int count);

}  // namespace tlvlink::bench
