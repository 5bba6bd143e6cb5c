#pragma once
// Post-training int8 quantization with calibration and mixed-precision fallback (`tlvlink
// quantize`). The scheme is calibrate.h's (and quantize/README.md's "Scheme"):
// per-channel (or per-tensor) symmetric int8 weights in [-127, 127], per-tensor asymmetric
// int8 activations, int32 bias at s_in * s_w[c], ReLU/ReLU6 fused into the op before them,
// pass-through ops sharing their input's parameters, Sigmoid output fixed at (1/256, -128).
//
// An operator that cannot meet the int8 constraints of the runtime (XNNPACK 2022 and the
// loader) stays fp32, with Quantize/Dequantize at its boundaries, and its LayerDecision says
// why; one layer never fails the whole model. The reasons:
//   - kept float by the user (QuantizerOptions::keep_float; "first"/"last" name the first/last
//     Conv2D or FullyConnected);
//   - no int8 kernel for the op type in the runtime;
//   - an activation whose range has no finite, normal int8 scale;
//   - a requantization multiplier outside the range XNNPACK accepts (conv/FC [2^-31, 256),
//     Add [2^-10, 256) per input, Mul [2^-16, 256), GlobalAveragePool [2^-8, 256));
//   - an int32 bias that only fits by raising a weight scale more than max_bias_scale_raise;
//   - a worst-case int32 accumulator |bias| + 255 * sum|w| that reaches 2^31;
//   - a Pad value outside the tensor's int8 range.
// Adjustments that keep a layer int8 are listed too: a weight scale raised so the bias fits, or
// so a negligible channel's multiplier stays above 2^-31 (its output would otherwise flush to 0).
//
//   auto stats = calibrate(fp32, frames);                      // one pass, all methods
//   auto ranges = select_ranges(*stats, {.method = CalibrationMethod::kPercentile});
//   auto q = quantize_model(fp32, ranges, {});
//   for (const LayerDecision& d : q->layers) if (d.precision == LayerPrecision::kFloat) ...
//   std::vector<std::byte> file = q->builder.finish();

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/calibrate.h"
#include "tlvlink/quantize/calibration_method.h"
#include "tlvlink/quantize/model_builder.h"
#include "tlvlink/quantize/observer.h"

namespace tlvlink::quantize {

// Graph input 0 of the float model, one frame at a time, already preprocessed (the caller
// runs the deployment preprocessing, tools/io/preprocess.h).
class InputSource {
 public:
  virtual ~InputSource() = default;
  // Fills `input` with the next frame; false at the end.
  virtual Result<bool> next(std::vector<float>& input) = 0;
};

// An InputSource over frames held in memory (tests, held-out sets).
class SpanInputSource final : public InputSource {
 public:
  explicit SpanInputSource(std::span<const std::vector<float>> frames) : frames_(frames) {}
  Result<bool> next(std::vector<float>& input) override;

 private:
  std::span<const std::vector<float>> frames_;
  size_t next_ = 0;
};

struct CalibrationStats {
  std::vector<TensorObserver> tensors;  // by float-model tensor index; constants unobserved
  uint64_t frames = 0;
};

struct CalibrationRunOptions {
  double averaging_constant = TensorObserver::kDefaultAveragingConstant;
  std::function<void(uint64_t frames_done)> on_frame;  // progress
};

// Runs the float model with the reference executor (all tensors exposed) on every frame of
// `inputs` and observes every float activation. Errors: a frame of the wrong size, a float
// model that overflows (NaN/Inf in an activation, named), no frames at all.
Result<CalibrationStats> calibrate(const Model& fp32, InputSource& inputs,
                                   const CalibrationRunOptions& options = {});
Result<CalibrationStats> calibrate(const Model& fp32, std::span<const std::vector<float>> inputs,
                                   const CalibrationRunOptions& options = {});

// One range per tensor under a calibration method (unobserved tensors stay unobserved).
std::vector<TensorRange> select_ranges(const CalibrationStats& stats,
                                       const CalibrationOptions& options);

enum class WeightGranularity : uint8_t { kPerChannel = 0, kPerTensor };
const char* weight_granularity_name(WeightGranularity g);  // "per-channel", "per-tensor"

// A correction added to the float bias of a Conv2D / FullyConnected before it is quantized (or
// copied, for a layer that stays fp32): one value per output channel. Made by
// correct_biases() (bias_correction.h); an unknown operator, an operator without a bias or a
// length other than its channel count is an error (kInvalidArgument).
struct BiasOffset {
  std::string op;
  std::vector<float> delta;
};

struct QuantizerOptions {
  WeightGranularity weights = WeightGranularity::kPerChannel;
  // Operator names kept in fp32; "first" / "last": the first / last Conv2D or FullyConnected.
  // An unknown name is an error (kInvalidArgument) listing the operators.
  std::vector<std::string> keep_float;
  float min_activation_range = kMinActivationRange;
  // A channel's weight scale may be raised up to this factor so its int32 bias fits (the
  // channel's largest weight then still uses >= 127/16 ~ 8 levels); beyond, the layer is fp32.
  double max_bias_scale_raise = 16.0;
  // Fuse a standalone Clamp that is exactly ReLU or ReLU6 into the Conv2D / FC / Add / Mul
  // before it (when it is that op's only consumer).
  bool fuse_clamps = true;
  std::string quantization_json;  // written into provenance.quantization
  std::vector<BiasOffset> bias_offsets;
};

enum class LayerPrecision : uint8_t { kInt8 = 0, kFloat };

struct LayerDecision {
  std::string op;  // operator name in the float model
  OpType type = OpType::kConv2D;
  LayerPrecision precision = LayerPrecision::kInt8;
  std::string reason;                    // why fp32 (empty when int8)
  std::vector<std::string> adjustments;  // int8 with changes, e.g. a raised weight scale
  std::string fused_into;                // a Clamp fused into this operator
  // Conv/FC in int8: SQNR of the dequantized weights against the float ones (weight-only
  // error); NaN otherwise; +inf when the weights are exactly representable.
  double weight_sqnr_db = std::numeric_limits<double>::quiet_NaN();
};

struct QuantizedModel {
  ModelBuilder builder;
  std::vector<LayerDecision> layers;  // one per float-model operator, in graph order
  size_t int8_ops = 0, float_ops = 0, fused_ops = 0;
  size_t conversions = 0;  // Quantize/Dequantize operators inserted
};

// The int8 / mixed form of a float model. Metadata is copied from the float model, minus its
// golden pairs. Errors: ranges missing for an activation that needs one, a model that is
// already quantized, unknown keep_float names, or a result the loader rejects (a bug).
Result<QuantizedModel> quantize_model(const Model& fp32, std::span<const TensorRange> ranges,
                                      const QuantizerOptions& options = {});

}  // namespace tlvlink::quantize
