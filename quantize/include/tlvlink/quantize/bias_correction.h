#pragma once
// Empirical bias correction (Nagel et al., "Data-Free Quantization", 2019, sec. 4.2, measured
// on calibration frames instead of derived from BatchNorm statistics): quantization shifts the
// *mean* of a layer's output a little in each channel, and those shifts add up through the
// network into a systematic error of the embedding (on the shipped model ~16 % of the int8
// error energy, all in one direction, which moves zero-shot decisions one way). For each
// Conv2D / FullyConnected with a bias, in graph order, the mean of (quantized - float) output per
// channel is measured on the calibration frames, with every earlier layer already corrected, and
// subtracted from that layer's float bias before it is quantized again. Only outputs inside the
// layer's activation range on both sides count (a clamped value says nothing about the shift).
//
//   auto ranges = select_ranges(*stats, copt);
//   auto corrected = correct_biases(fp32, ranges, qopt, calibration_frames, {});
//   // corrected->model: the int8 model built with corrected->offsets; ->layers: what moved

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/executor.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/quantizer.h"

namespace tlvlink::quantize {

struct BiasCorrectionOptions {
  size_t max_frames = 64;  // calibration frames used (the first ones); 1..frames.size()
  // Executor running both models (XNNPACK is what deploys and is ~50x faster; the reference
  // executor agrees with it within 1 LSB).
  ExecutorKind executor = ExecutorKind::kXnnpack;
  std::function<void(size_t layers_done, size_t layers)> on_layer;  // progress
};

struct BiasCorrectionLayer {
  std::string op;
  bool int8 = false;          // the layer's output is int8 (else fp32)
  double step = 0;            // its int8 step (0 for fp32)
  double mean_abs_shift = 0;  // mean over channels of |mean(q - f)| before this correction
  double max_abs_shift = 0;   // largest |mean(q - f)| of a channel
  size_t channels = 0, channels_measured = 0;  // channels with at least one in-range value
};

struct CorrectedModel {
  QuantizedModel model;  // quantize_model(fp32, ranges, options + offsets)
  std::vector<BiasOffset> offsets;
  std::vector<BiasCorrectionLayer> layers;
  size_t frames = 0;
};

// How many layers correct_biases() measures: the Conv2D / FullyConnected operators with a bias.
size_t correctable_layers(const Graph& graph);

// Errors: no frames, a frame of the wrong size, executor failures (named), and whatever
// quantize_model returns.
Result<CorrectedModel> correct_biases(const Model& fp32, std::span<const TensorRange> ranges,
                                      const QuantizerOptions& options,
                                      std::span<const std::vector<float>> frames,
                                      const BiasCorrectionOptions& correction = {});

}  // namespace tlvlink::quantize
