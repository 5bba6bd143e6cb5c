#pragma once
// Error of a quantized model against its float original, per layer and end to end, on frames
// that were not used for calibration. Both models run on the same frames; every float-model
// operator output that still exists in the quantized model (same tensor name; int8 tensors are
// dequantized with their own parameters) is compared with the float value:
//   SQNR      10 log10(sum f^2 / sum (f - q)^2) in dB (+inf when identical)
//   cosine    sum f q / sqrt(sum f^2 sum q^2) over all compared values
//   max_abs   max |f - q|
//   rmse / scale   RMS error in units of the tensor's int8 step (~0.29 is pure rounding of a
//             uniform signal; much more means clipping or accumulated error upstream)
// Errors accumulate through the network: a layer's figures include everything before it.
//
//   auto e = compare_models(fp32, int8, heldout_frames, {});
//   for (const TensorError& t : e->layers) printf("%s %.1f dB\n", t.op.c_str(), t.error.sqnr_db());

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/executor.h"
#include "tlvlink/graph.h"
#include "tlvlink/model.h"

namespace tlvlink::quantize {

// Running sums of reference (float) vs approximation.
struct ErrorStats {
  double ref_energy = 0, err_energy = 0, dot = 0, approx_energy = 0, max_abs = 0;
  uint64_t count = 0;

  void add(std::span<const float> ref, std::span<const float> approx);
  double sqnr_db() const;  // +inf when err_energy == 0
  double cosine() const;   // 1 when both are all zero
  double rmse() const;
};

struct TensorError {
  std::string tensor;  // float-model tensor name
  std::string op;      // operator producing it
  OpType type = OpType::kConv2D;
  DType dtype = DType::kFloat32;  // its dtype in the quantized model
  float scale = 0;                // int8 step (0 for an fp32 tensor)
  ErrorStats error;
  double rmse_over_scale() const {
    return scale > 0 ? error.rmse() / static_cast<double>(scale) : 0;
  }
};

struct ModelError {
  std::vector<TensorError> layers;   // float-model operator order
  ErrorStats embedding;              // graph output metadata.embedding_output (else output 0)
  std::vector<double> frame_cosine;  // embedding cosine per frame
  uint64_t frames = 0;
  double mean_cosine() const;
  double min_cosine() const;
};

struct CompareOptions {
  bool per_layer = true;  // false: outputs only (no exposed tensors; faster, any executor)
  // Executor of the quantized model (the float model always runs on the reference executor,
  // the numerical reference). Per-layer comparison needs every tensor exposed.
  ExecutorKind quantized_executor = ExecutorKind::kReference;
  int threads = 1;
  std::function<void(uint64_t frames_done)> on_frame;  // progress
};

// Errors: models whose input 0 / embedding output differ in size, frames of the wrong size,
// executor failures.
Result<ModelError> compare_models(const Model& fp32, const Model& quantized,
                                  std::span<const std::vector<float>> frames,
                                  const CompareOptions& options = {});

// The embedding output (metadata.embedding_output, else output 0; int8 dequantized) of `model`
// on each frame. For comparing several variants against one float reference without re-running
// it (the sweep).
Result<std::vector<std::vector<float>>> embeddings(const Model& model,
                                                   std::span<const std::vector<float>> frames,
                                                   ExecutorKind kind = ExecutorKind::kReference,
                                                   int threads = 1);
// Embedding error of `outputs` against `reference`, frame by frame (layers left empty).
ModelError compare_embeddings(std::span<const std::vector<float>> reference,
                              std::span<const std::vector<float>> outputs);

}  // namespace tlvlink::quantize
