#pragma once
// Small float graphs and helpers for the quantizer tests.

#include <memory>
#include <string>
#include <vector>

#include "tlvlink/model.h"
#include "tlvlink/quantize/model_builder.h"
#include "tlvlink/quantize/quantizer.h"

namespace tlvlink::quantizer_test {

// One Conv2D (OHWI weights [cout, k, k, cin], 'same' padding) from input [1, h, w, cin].
std::vector<std::byte> conv_model(int32_t h, int32_t w, int32_t cin, int32_t cout, int32_t k,
                                  const std::vector<float>& weights, const std::vector<float>& bias,
                                  Activation act = Activation::kNone);

// input [1,8,8,3] -> conv1 (3x3, relu6) -> conv2 (1x1) -> add(conv2, conv1) -> conv3 (3x3 /2,
// relu) -> gap -> reshape [1,8] -> fc (8 -> 16) -> output. Seeded random weights.
std::vector<std::byte> small_network(uint64_t seed);
// The network seed the accuracy floors below were measured with (frames vary with the test seed).
inline constexpr uint64_t kNetworkSeed = 7;

// `count` random frames of `elements` values in [lo, hi].
std::vector<std::vector<float>> random_frames(size_t count, size_t elements, float lo, float hi,
                                              uint64_t seed);

// calibrate (minmax unless told) -> quantize_model; failures are test failures (nullopt).
struct Quantized {
  quantize::QuantizedModel q;
  std::unique_ptr<Model> model;  // the loaded result
};
std::unique_ptr<Quantized> quantize_for_test(
    const Model& fp32, const std::vector<std::vector<float>>& frames,
    const quantize::QuantizerOptions& options = {},
    quantize::CalibrationMethod method = quantize::CalibrationMethod::kMinMax);

// Runs `model` on `input` with the reference executor; returns graph output 0 as floats.
std::vector<float> run(const Model& model, const std::vector<float>& input);

const quantize::LayerDecision* decision(const quantize::QuantizedModel& q, const std::string& op);
// Operator of the quantized graph writing the tensor named `name` (nullptr if none).
const Operator* producer_of(const Model& m, const std::string& tensor);
int count_ops(const Model& m, OpType type);

}  // namespace tlvlink::quantizer_test
