#pragma once
#ifndef TLVLINK_QUANTIZE_PRIVATE
#error "quantizer_internal.h is internal to quantize: include its public headers instead"
#endif
// Internals of the quantizer: the operator plan (fusion, denylist), weight/bias quantization
// with the int8 constraints, and the graph emitter.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/graph.h"
#include "tlvlink/quantize/quantizer.h"

namespace tlvlink::quantize::quantizer_internal {

// Requantization ratios XNNPACK's qs8 operators accept at creation (operators/*.c of the
// 2022-02 snapshot Debian ships): outside them xnn_create_* returns unsupported_parameter.
// Conv2D / FC use the loader's [kMinRequantMultiplier, kMaxRequantMultiplier) (quant_math.h).
inline constexpr float kAddRatioMin = 0x1p-10f, kAddRatioMax = 0x1p8f;  // s_a/s_out, s_b/s_out
inline constexpr float kMulRatioMin = 0x1p-16f, kMulRatioMax = 0x1p8f;  // s_a*s_b/s_out
inline constexpr float kGapRatioMin = 0x1p-8f, kGapRatioMax = 0x1p8f;   // s_in/s_out
// A bias quantized to at most 2^30 leaves half of the int32 accumulator for the products
// (255 * 127 * K < 2^30 holds for K < 33,155 inputs per output).
inline constexpr double kMaxBiasMagnitude = 0x1p30;
// The loader's bound on |bias| + 255 * sum|w| (validate_conv_fc.cc).
inline constexpr int64_t kAccumulatorLimit = int64_t{1} << 31;
inline constexpr int64_t kMaxCenteredInput = 255;

// printf into a std::string (messages of decisions and adjustments).
[[gnu::format(printf, 1, 2)]] std::string strf(const char* format, ...);

// ---- plan.cc ----
struct OpPlan {
  Activation activation = Activation::kNone;  // after fusing a following Clamp
  int32_t output = kNoTensor;                 // the float-model tensor this op now produces
  int32_t fused_clamp = -1;                   // operator index of a Clamp fused into this op
  int32_t fused_into = -1;                    // for that Clamp: the operator it joined
  bool keep_float = false;                    // on the user's denylist
};
// One entry per float-model operator. Error (kInvalidArgument) for unknown keep_float names.
Result<std::vector<OpPlan>> make_plan(const Graph& graph, const QuantizerOptions& options);

// The activation fused into a Conv2D / FullyConnected / Add / Mul (kNone for other ops).
Activation activation_of(const Operator& op);

// Whether the runtime (reference and XNNPACK executors) has an int8 kernel for the op type.
bool has_int8_kernel(OpType type);

// ---- weights.cc ----
struct LinearRequest {
  std::span<const float> weights;  // [cout, ...] row-major
  int32_t cout = 0;
  std::span<const float> bias;  // [cout] or empty
  float input_scale = 0, output_scale = 0;
  WeightGranularity granularity = WeightGranularity::kPerChannel;
  double max_bias_scale_raise = 16.0;
};
struct LinearWeights {
  std::vector<int8_t> values;
  std::vector<float> scales;       // cout entries (per-channel) or 1 (per-tensor)
  std::vector<int32_t> bias;       // empty without bias
  std::vector<float> bias_scales;  // same length as scales
  std::vector<std::string> adjustments;
  std::string failure;  // non-empty: the layer cannot be int8, and why
  double weight_sqnr_db = 0;
};
LinearWeights quantize_linear(const LinearRequest& request);

// Symmetric int8 of `values` at `scale`, always inside [-127, 127] (never -128).
void quantize_symmetric(std::span<const float> values, float scale, std::span<int8_t> out);
// 10 log10(sum ref^2 / sum (ref - approx)^2); +inf when equal, NaN for an all-zero reference
// with error.
double sqnr_db(double signal_energy, double error_energy);

// Per-tensor asymmetric parameters for [lo, hi] with the range floor, or an error message when
// no finite normal scale exists.
struct ActivationParams {
  QuantSpec spec;
  std::string failure;
};
ActivationParams activation_params(const TensorRange& range, float min_range);

// ---- emit.cc ----
Result<QuantizedModel> emit_quantized(const Model& fp32, std::span<const TensorRange> ranges,
                                      const QuantizerOptions& options,
                                      const std::vector<OpPlan>& plan);

}  // namespace tlvlink::quantize::quantizer_internal
