#pragma once
// A small int8 model (Quantize -> Conv2D -> GlobalAveragePool -> Reshape -> FC -> Dequantize) whose
// every field a test can mutate before writing, to check that the loader rejects each defect.

#include <functional>
#include <vector>

#include "tlvlink/quantize/model_builder.h"

namespace tlvlink::testing {

struct TinyInt8Model {
  // Quantization / data knobs; tests change them to craft bad files.
  std::vector<float> conv_weight_scales{0.01f, 0.02f, 0.015f, 0.03f};
  std::vector<int8_t> conv_weights;  // [4,3,3,3]
  std::vector<int32_t> conv_bias{100, -50, 0, 7};
  float input_scale = 1.0f / 64, output_scale = 0.05f, bias_scale_override = 0;
  int32_t input_zero_point = 0, conv_zero_point = -10;
  int32_t conv_weight_axis = 0;
  bool conv_has_bias = true;
  Conv2DParams conv{3, 3, 1, 1, 1, 1, 1, 1, 1, 1, 1, Activation::kRelu};
  std::vector<int32_t> conv_output_shape{1, 8, 8, 4};
  // Hook run on the builder after the graph is added (extra tensors, ops, metadata).
  std::function<void(quantize::ModelBuilder&)> tweak;

  TinyInt8Model();
  std::vector<std::byte> build() const;
};

}  // namespace tlvlink::testing
