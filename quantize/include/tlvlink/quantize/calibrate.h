#pragma once
// Minimal post-training int8 conversion: min/max calibration with the reference executor, then
// a rewrite of a float model into tlvlink's int8 scheme:
//   - Quantize after each float graph input, Dequantize before each graph output (I/O stays fp32);
//   - activations int8, per-tensor asymmetric, range always including 0, width floored at
//     kMinActivationRange;
//   - conv / FC weights int8 per-channel symmetric in [-127, 127] (axis 0), int32 bias with
//     scale s_in * s_w[c];
//   - pass-through ops (Reshape, Pad, MaxPool2D, Clamp, ResizeBilinear) share their input's
//     parameters; Sigmoid outputs use (1/256, -128).
// convert_to_int8 is quantize_model (quantizer.h) with its defaults; `tlvlink quantize` adds the
// calibration methods, mixed-precision fallback and the error report on top.
//
//   auto ranges = collect_ranges(fp32_model, calibration_inputs);
//   auto builder = convert_to_int8(fp32_model, *ranges, {});
//   std::vector<std::byte> file = builder->finish();

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/model_builder.h"
#include "tlvlink/quantize/model_copy.h"  // metadata_spec_from (the model writer)

namespace tlvlink::quantize {

// Narrowest real range an activation gets (a dead or constant tensor still has a normal scale).
inline constexpr float kMinActivationRange = 0x1p-12f;
// Smallest per-channel weight scale (an all-zero channel still gets a normal, positive scale).
inline constexpr float kMinWeightScale = 0x1p-20f;

struct TensorRange {
  float min = std::numeric_limits<float>::infinity();
  float max = -std::numeric_limits<float>::infinity();
  bool observed() const { return min <= max; }
};

// Runs `model` with the reference executor (all tensors exposed) on each input (the bytes of
// graph input 0, as float) and records every float activation's [min, max]. Constants and
// non-float tensors stay unobserved.
Result<std::vector<TensorRange>> collect_ranges(const Model& model,
                                                std::span<const std::vector<float>> inputs);

// Per-tensor asymmetric int8 parameters covering [min, max] ∪ {0} (computed in double, so even
// +-3e38 gets a finite scale); empty when no finite normal scale exists.
QuantSpec activation_quant(float min, float max, float min_range = kMinActivationRange);

struct Int8ConversionOptions {
  float min_activation_range = kMinActivationRange;
  std::string quantization_json;  // written into provenance.quantization
};

// The int8 form of a float model, as a builder (so callers can add golden pairs before
// finish()). Metadata is copied from the float model, minus its golden pairs.
Result<ModelBuilder> convert_to_int8(const Model& fp32, std::span<const TensorRange> ranges,
                                     const Int8ConversionOptions& options = {});

// Runs `model` once on `input` (the bytes of graph input 0) with the reference executor and
// returns the bytes of graph output 0: what a golden pair records.
Result<std::vector<std::byte>> run_reference(const Model& model, std::span<const std::byte> input);

}  // namespace tlvlink::quantize
