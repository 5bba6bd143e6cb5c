#pragma once
// Test harness comparing the XNNPACK executor with the reference executor.
//
// A test describes a graph once, with float data (TGraph). The harness writes it as an fp32
// model, and as an int8 model quantized the way the quantizer does it: activations calibrated
// from a reference fp32 run (range scaled by a random factor so some values hit the rails),
// weights symmetric per-channel, bias int32 at s_in * s_w[c]. Both executors then run the same
// inputs and the outputs are compared:
//   int8: within 1 LSB (kInt8Tolerance) for every operator whose inputs agree exactly; a
//         difference inherited from an earlier operator is reported, not held against the next.
//   fp32: |xnn - ref| <= kFloatRelTolerance * sqrt(K) * M, where K is the summed reduction
//         length along the graph and M the same graph run on |inputs|, |weights| (a bound on
//         sum |x * w| for every output element).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "support/random.h"
#include "support/test_models.h"
#include "tlvlink/executor.h"
#include "tlvlink/graph.h"
#include "tlvlink/model.h"

namespace tlvlink::testing {

// Round-half-even (XNNPACK) vs other tie-breaks and float-vs-double scale products differ by
// at most one step of the output grid (quantization.md).
inline constexpr int kInt8Tolerance = 1;
// fp32 unit roundoff is 6e-8; summing K products in another order (FMA, blocking) gives an
// error that grows like eps * sqrt(K) * sum|x*w|. 1e-5 leaves > 100x margin and still catches
// any layout or indexing mistake, which produces O(1) relative errors.
inline constexpr double kFloatRelTolerance = 1e-5;

enum class TKind : uint8_t { kActivation, kWeights, kBias, kConstant };

struct TTensor {
  std::string name;
  std::vector<int32_t> shape;
  TKind kind = TKind::kActivation;
  std::vector<float> data;  // constants only
};

struct TOp {
  OpType type;
  std::string name;
  std::vector<int32_t> inputs;
  int32_t output;
  OpParams params;
};

// A graph with float data. Quantize/Dequantize are not used here (they have their own tests).
struct TGraph {
  std::vector<TTensor> tensors;
  std::vector<TOp> ops;
  std::vector<int32_t> inputs, outputs;

  int32_t activation(std::string name, std::vector<int32_t> shape);
  int32_t constant(std::string name, std::vector<int32_t> shape, std::vector<float> data,
                   TKind kind = TKind::kConstant);
  // Adds `type` producing a new activation of `out_shape`; returns the output tensor.
  int32_t op(OpType type, std::string name, std::vector<int32_t> inputs,
             std::vector<int32_t> out_shape, OpParams params = NoParams{});
  const TTensor& tensor(int32_t i) const { return tensors[static_cast<size_t>(i)]; }
};

struct QParam {
  float scale = 1.0f;
  int32_t zero_point = 0;
};

// Float graph, or its |data| variant (constants and inputs made non-negative, activations off).
std::vector<std::byte> build_fp32(const TGraph& graph);
TGraph magnitude_graph(const TGraph& graph);
// Summed reduction length along the graph (conv: KH*KW*Cin/g, FC: Cin, GAP: H*W, ...).
double reduction_length(const TGraph& graph);

// int8 model from the float graph and one QParam per tensor (activations and plain constants).
std::vector<std::byte> build_int8(const TGraph& graph, const std::vector<QParam>& quant);

// Calibrates quantization from a reference fp32 run on `inputs`; each range is multiplied by a
// random factor in [range_lo, range_hi] (< 1 forces saturation at the rails).
std::vector<QParam> calibrate(const TGraph& graph, const Model& fp32_model,
                              const std::vector<std::vector<float>>& inputs, Rng& rng,
                              float range_lo = 0.7f, float range_hi = 1.2f);

// Raw bytes of every tensor after a run (empty for tensors the executor does not keep).
struct RunOutput {
  std::vector<std::vector<std::byte>> tensors;
};

// Runs `model` with expose_all_tensors on the given raw input bytes. Fails the test on error.
RunOutput run(const Model& model, ExecutorKind kind,
              const std::vector<std::vector<std::byte>>& inputs, int threads = 1);

std::vector<std::byte> to_bytes(const std::vector<float>& v);
std::vector<std::byte> to_bytes(const std::vector<int8_t>& v);
std::vector<std::byte> quantize_input(const std::vector<float>& v, QParam q);

// Aggregated agreement figures across many comparisons (printed by tests).
struct Agreement {
  size_t int8_elements = 0, int8_exact = 0;
  int int8_max_diff = 0;             // over operators whose inputs agreed exactly
  int int8_max_propagated_diff = 0;  // downstream of an earlier difference (reported only)
  size_t float_elements = 0;
  double float_max_ratio = 0;  // max |diff| / allowed
  std::string summary() const;
};

// Compares every activation of the int8 model (ops in order, isolation rule above). Adds gtest
// failures naming the operator and element on violation.
void compare_int8(const Model& model, const RunOutput& ref, const RunOutput& xnn, Agreement& agg);

// Compares graph outputs of the fp32 model with the magnitude bound from `magnitude`.
void compare_fp32(const Model& model, const RunOutput& ref, const RunOutput& xnn,
                  const RunOutput& magnitude, double k, Agreement& agg);

// Full check of one float graph: fp32 (XNNPACK vs reference, derived tolerance) and int8
// (calibrated, XNNPACK vs reference within 1 LSB). Inputs are random in [-in_range, in_range].
void check_graph(const TGraph& graph, Rng& rng, Agreement& agg, float in_range = 1.0f);

}  // namespace tlvlink::testing
