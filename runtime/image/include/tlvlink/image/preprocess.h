#pragma once
// The model's input preprocessing, as its InputSpec describes it: crop, resize to the model size
// (bilinear, area or nearest), channel order, pixel/255, (x - mean) / std, and for an int8 input
// tensor the input's quantization. This is the one implementation for inference, calibration and
// training (the shipped models were trained through it): a plan is made once from the spec and
// the size of the frames that will come; run() then writes graph input 0 in one pass into
// caller-owned memory, allocating nothing.
//
// The arithmetic is exactly that of the staged reference (crop, resize to uint8 with
// round-half-away, normalise in float); tests/image/preprocess_plan_test.cc holds that reference
// and checks the plan against it bit for bit. Compiled with -ffp-contract=off so an ARM board
// computes the same floats as the host (GCC would otherwise fuse a*b+c into FMA there).

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/graph.h"
#include "tlvlink/image/image.h"
#include "tlvlink/metadata.h"

namespace tlvlink::image {

namespace detail {
// Where one output row or column of a resize reads the source axis.
struct ResizeTap {
  int32_t i0 = 0, i1 = 0;  // bilinear: the two neighbours; area: [i0, i1); nearest: i0
  float w = 0;             // bilinear: the weight of i1
};
}  // namespace detail

// How run() encodes the values: float, or int8 with the input tensor's scale and zero point
// (quant_math.h quantize_value, what the runtime's Quantize operator computes).
struct InputEncoding {
  DType dtype = DType::kFloat32;  // kFloat32 or kInt8
  float scale = 1;
  int32_t zero_point = 0;
};
// The encoding graph input 0 of a model expects (kModelUnsupported for other dtypes).
Result<InputEncoding> input_encoding(const Tensor& input);

class PreprocessPlan {
 public:
  // Frames of frame_width x frame_height with frame_channels (1 or 3) into the spec's tensor
  // [1, spec.height, spec.width, spec.channels]. Errors: background subtraction (not
  // implemented: kModelUnsupported), channels other than 1 or 3, a crop outside the frame
  // (kShapeMismatch, a frame that does not fit the model is bad data).
  static Result<PreprocessPlan> create(const InputSpec& spec, int32_t frame_width,
                                       int32_t frame_height, int32_t frame_channels,
                                       InputEncoding encoding = {});

  int32_t frame_width() const { return frame_width_; }
  int32_t frame_height() const { return frame_height_; }
  int32_t frame_channels() const { return frame_channels_; }
  size_t output_values() const;  // height * width * channels
  size_t output_bytes() const;   // output_values() * 4 (float) or * 1 (int8)
  const InputEncoding& encoding() const { return encoding_; }
  // Every value run() can write is finite: (v / 255 - mean) / std over v in [0, 255] (int8
  // outputs always are). Checked once here, so the frame path can skip the executor's scan.
  bool outputs_finite() const { return outputs_finite_; }

  // One pass over the frame; no allocation. The frame must have the planned size and channels
  // and `out` exactly output_bytes() (kShapeMismatch otherwise).
  Status run(const ImageView& frame, std::span<std::byte> out) const;
  // Float plans only.
  Status run(const ImageView& frame, std::span<float> out) const;
  // run()'s first stage alone: the crop resized to height x width with the spec's filter, as
  // uint8 pixels in the frame's channel layout (what run() then reorders and normalises). The
  // trainer augments frames at the sensor's size and resizes them through this, so training
  // and the board compute every model pixel alike. `out` exactly height * width * frame
  // channels bytes (kShapeMismatch otherwise); no allocation.
  Status resize(const ImageView& frame, std::span<uint8_t> out) const;
  int32_t height() const { return height_; }
  int32_t width() const { return width_; }

 private:
  using Tap = detail::ResizeTap;  // per output row/column, into the (cropped) frame
  template <typename Out>
  void run_typed(const ImageView& frame, Out* out) const;
  void resized_values(const ImageView& frame, int32_t y, int32_t x, uint8_t v[3]) const;
  Status check(const ImageView& frame, size_t out_bytes) const;

  int32_t frame_width_ = 0, frame_height_ = 0, frame_channels_ = 0;
  int32_t height_ = 0, width_ = 0, channels_ = 0;
  int32_t crop_x_ = 0, crop_y_ = 0;
  ResizeFilter filter_ = ResizeFilter::kBilinear;
  bool identity_ = false;  // bilinear to the same size: a copy
  ChannelOrder order_ = ChannelOrder::kRGB;
  float mean_[4] = {}, std_[4] = {};
  InputEncoding encoding_;
  bool outputs_finite_ = false;
  std::vector<Tap> rows_, cols_;
};

// Conveniences for host tools (allocate): the float input tensor of one image, and a resized
// copy with the preprocessing's own filters (bilinear with half-pixel centres, as
// ResizeBilinear align_corners=false).
Result<std::vector<float>> preprocess(const ImageView& image, const InputSpec& spec);
Result<std::vector<float>> preprocess(const Image& image, const InputSpec& spec);
Image resize_bilinear(const Image& image, int32_t height, int32_t width);
// A copy resized with `filter` exactly as PreprocessPlan::resize does (no crop).
Result<Image> resize(const ImageView& image, int32_t height, int32_t width, ResizeFilter filter);

}  // namespace tlvlink::image
