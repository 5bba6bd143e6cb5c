#pragma once
// How closely two runs of a model must agree, per output tensor kind. One rule for `tlvlink
// verify`, `infer --compare-executors`, the board smoke test and the daemon's start-up self-test:
//   - an int8 output: 1 LSB (XNNPACK and the reference may round half-way cases differently);
//   - a float output behind a Dequantize: 1 LSB of that int8 tensor's scale;
//   - a float output of a float graph: 1e-4 of the output's largest magnitude (summation order
//     differs between kernels; per-element relative error is meaningless near zero).
// Values are compared as floats (int8 outputs dequantized with their parameters); a NaN or Inf
// anywhere fails.

#include <cstddef>
#include <cstdint>
#include <span>

#include "tlvlink/graph.h"

namespace tlvlink::verify {

inline constexpr double kFloatRelTolerance = 1e-4;
inline constexpr double kInt8LsbTolerance = 1.0;
// Float slack on a 1-LSB dequantized comparison (the dequantize itself rounds).
inline constexpr double kLsbSlack = 1.0 + 1e-5;

struct OutputComparison {
  double max_abs_error = 0;
  double tolerance = 0;
  double error_in_lsb = -1;  // max_abs_error / LSB for (de)quantized outputs, else -1
  const char* rule = "";
  bool pass = false;
};

// Element i of a tensor's bytes as a float (int8 dequantized, int32/uint8 widened).
float output_value(const Tensor& tensor, std::span<const std::byte> bytes, size_t i);

// `got` against `want` for graph output `output`, both as floats. No allocation.
OutputComparison compare_output(const Graph& graph, int32_t output, std::span<const float> got,
                                std::span<const float> want);
// The same on the tensor's raw bytes (both of the output's size). No allocation.
OutputComparison compare_output_bytes(const Graph& graph, int32_t output,
                                      std::span<const std::byte> got,
                                      std::span<const std::byte> want);

}  // namespace tlvlink::verify
