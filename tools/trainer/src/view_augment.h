#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "view_augment.h is internal to tools/trainer: include its public headers instead"
#endif
// The sensor-view augmentation (trainer.h ViewAugmentOptions, README "Sensor-view
// augmentation"): a touch frame at the sensor's processed size becomes one of the frames real
// sensors and links give of the same touch (mounting, optics, LEDs, dust, focus, noise, codec),
// then the model's input through the model's own resize (image::PreprocessPlan::resize, the
// board's arithmetic). No libtorch. One ViewAugmenter per thread: it owns JPEG handles and
// scratch buffers, sized once; make() allocates nothing after the first call at a given size
// (libjpeg-turbo mallocs its own working memory inside each call).

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/image/convert.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/image/resample.h"
#include "tlvlink/trainer/trainer.h"

namespace tlvlink::trainer {

// What one view drew: the components applied and their main parameter (tests, the log).
struct ViewDraw {
  uint32_t applied = 0;  // ViewComponent bits
  enum class Codec : uint8_t { kNone, kJpeg, kMjpegScaled, kYuyv } codec = Codec::kNone;
  int32_t quality = 0;    // kJpeg, kMjpegScaled
  int32_t dct_scale = 1;  // kMjpegScaled: 2 or 4
  double blur_sigma = 0, noise_dn = 0;
};

class ViewAugmenter {
 public:
  // Frames of frame_width x frame_height RGB into the model input `spec` (its size and resize
  // filter; no crop). `camera` is how a YUYV camera delivers such frames (DIGIT: transposed),
  // so its chroma pairs fall where the real camera's do. Errors: what PreprocessPlan::create
  // refuses, odd sides.
  static Result<ViewAugmenter> create(int32_t frame_width, int32_t frame_height,
                                      const InputSpec& spec,
                                      image::Orientation camera = image::Orientation::kUpright);

  // One view of `frame` (frame_height x frame_width x 3) into `out` (the model's height x width
  // x 3 uint8): the components of `components` each drawn on or off with its probability, then
  // the model's resize. Same (components, seed, frame) -> same bytes.
  Status make(std::span<const uint8_t> frame, uint32_t components, uint64_t seed,
              std::span<uint8_t> out, ViewDraw* draw = nullptr);
  // The codec twin of make(frame, components, seed): every draw the same but the codec's,
  // which (on or off, kind, quality) comes from `codec_seed`. The pair differs by the link
  // alone, as a frame and its re-encoding do.
  Status make_codec_twin(std::span<const uint8_t> frame, uint32_t components, uint64_t seed,
                         uint64_t codec_seed, std::span<uint8_t> out, ViewDraw* draw = nullptr);

  int32_t frame_width() const { return width_; }
  int32_t frame_height() const { return height_; }

 private:
  ViewAugmenter() = default;
  Status codec(uint64_t& rng, ViewDraw& draw);
  Status make_view(std::span<const uint8_t> frame, uint32_t components, uint64_t seed,
                   const uint64_t* codec_seed, std::span<uint8_t> out, ViewDraw* draw);

  int32_t width_ = 0, height_ = 0;
  image::Orientation camera_ = image::Orientation::kUpright;
  image::PreprocessPlan resize_;
  std::vector<float> work_, tmp_;  // float frame and the blur's intermediate
  std::vector<uint8_t> frame8_, codec8_, big8_;
  std::unique_ptr<image::JpegEncoder> encoder_;  // not movable themselves
  std::unique_ptr<image::JpegDecoder> decoder_;
  image::Resampler up2_, up4_;  // the MJPEG emulation's camera-field enlargement
};

// The seed of view `view` (0 or 1) of sample `index` at step `step`.
uint64_t view_seed(uint64_t run_seed, int64_t step, int64_t index, int32_t view);

}  // namespace tlvlink::trainer
