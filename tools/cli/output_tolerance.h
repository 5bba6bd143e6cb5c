#pragma once
// How closely two executors' outputs must agree, per output tensor kind (shared by `verify` and
// `infer --compare-executors`):
//   - an int8 output: 1 LSB (XNNPACK and the reference may round half-way cases differently);
//   - a float output behind a Dequantize: 1 LSB of that int8 tensor's scale;
//   - a float output of a float graph: 1e-4 of the output's largest magnitude (summation order
//     differs between kernels; per-element relative error is meaningless near zero).

#include <cstdint>
#include <span>

#include "tlvlink/graph.h"

namespace tlvlink::cli {

struct OutputComparison {
  double max_abs_error = 0;
  double tolerance = 0;
  double error_in_lsb = -1;  // max_abs_error / LSB for (de)quantized outputs, else -1
  const char* rule = "";
  bool pass = false;
};

// Compares `got` against `want` (both as floats) for graph output `output`.
OutputComparison compare_output(const Graph& graph, int32_t output, std::span<const float> got,
                                std::span<const float> want);

}  // namespace tlvlink::cli
