#pragma once
// The live image path applied to an already rendered processed frame: the sensor's raw camera
// output (RawCamera::encode_frame: the Mini's MJPEG 3280x2464 q90, DIGIT's YUYV, ...) recovered
// by RawDecoder, the board's FrameDecoder. A frame made this way is what tlvlinkd decodes from
// that sensor, noise grain and compression artefacts included; datasets rendered for heads or
// encoders that run on the board can train on it (`tlvlink sim feel --live-path`) instead of a
// JPEG round trip at the processed size, which smooths the grain the live path keeps
// (firmware/models/README.md, "Live path vs offline").
//
// Made once (allocates the camera's and decoder's buffers); apply() allocates nothing of its own
// after the first frame (libjpeg-turbo mallocs its working memory per call). One per thread.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/sim/raw_camera.h"
#include "tlvlink/sim/sensor.h"

namespace tlvlink::sim {

class LivePath {
 public:
  static Result<std::unique_ptr<LivePath>> create(const SensorProfile& profile,
                                                  const RawOptions& options = {});

  // rgb: the profile's processed frame (height * width * 3), replaced by what the live path
  // recovers from it. A frame of another size is a kShapeMismatch.
  Status apply(std::span<uint8_t> rgb);

  const SensorProfile& profile() const { return camera_->profile(); }

 private:
  std::unique_ptr<RawCamera> camera_;
  std::unique_ptr<RawDecoder> decoder_;
  RawFrame raw_;
  std::vector<uint8_t> recovered_;
};

}  // namespace tlvlink::sim
