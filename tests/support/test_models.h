#pragma once
// Helpers to build and load small models in tests.

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "tlvlink/model.h"
#include "tlvlink/quantize/model_builder.h"

namespace tlvlink::testing {

// Loads a builder's output; on failure records a gtest failure with the loader's message and
// returns nullptr (callers: `auto m = load_model(b.finish()); ASSERT_NE(m, nullptr);`).
std::unique_ptr<Model> load_model(const std::vector<std::byte>& file);

// Loads a file expected to be rejected; returns the error (kOk if it unexpectedly loaded).
Error load_error(const std::vector<std::byte>& file);

// A file whose flatbuffer a test edited, with its integrity trailer recomputed (unsigned), so the
// loader's checks behind the hash see the edit.
std::vector<std::byte> resealed(const std::vector<std::byte>& file);

// Symmetric per-channel int8 quantization of OHWI / [Cout, ...] float weights along axis 0:
// scale[c] = max|w_c| / 127 (floored at kMinWeightScale), values in [-127, 127].
struct QuantizedWeights {
  std::vector<int8_t> values;
  std::vector<float> scales;
};
QuantizedWeights quantize_weights_per_channel(std::span<const float> weights, int32_t out_channels);

// int32 bias for a quantized conv/FC: round(bias / (input_scale * weight_scale[c])).
std::vector<int32_t> quantize_bias(std::span<const float> bias, float input_scale,
                                   std::span<const float> weight_scales);

// Typed views over raw tensor bytes.
template <typename T>
std::span<const T> as_span(std::span<const std::byte> bytes) {
  return {reinterpret_cast<const T*>(bytes.data()), bytes.size() / sizeof(T)};
}
template <typename T>
std::span<T> as_mutable_span(std::span<std::byte> bytes) {
  return {reinterpret_cast<T*>(bytes.data()), bytes.size() / sizeof(T)};
}

}  // namespace tlvlink::testing
