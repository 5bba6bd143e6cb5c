#include "cli/output_tolerance.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tlvlink::cli {
namespace {

constexpr double kFloatRelTolerance = 1e-4;
constexpr double kInt8LsbTolerance = 1.0;
// Float slack on a 1-LSB dequantized comparison (the dequantize itself rounds).
constexpr double kLsbSlack = 1.0 + 1e-5;

// The quantized tensor a float graph output is dequantized from, if any.
const Tensor* dequantized_from(const Graph& g, int32_t output) {
  for (const Operator& op : g.operators) {
    if (op.output == output && op.type == OpType::kDequantize) return &g.tensor(op.inputs[0]);
  }
  return nullptr;
}

}  // namespace

OutputComparison compare_output(const Graph& graph, int32_t output, std::span<const float> got,
                                std::span<const float> want) {
  OutputComparison c;
  double max_ref = 0;
  for (size_t k = 0; k < got.size() && k < want.size(); ++k) {
    const double g = static_cast<double>(got[k]), w = static_cast<double>(want[k]);
    // A NaN anywhere must fail, never compare as "not greater".
    c.max_abs_error = std::isfinite(g - w) ? std::max(c.max_abs_error, std::fabs(g - w))
                                           : std::numeric_limits<double>::infinity();
    max_ref = std::max(max_ref, std::fabs(w));
  }
  if (got.size() != want.size()) c.max_abs_error = std::numeric_limits<double>::infinity();
  const Tensor& out = graph.tensor(output);
  const Tensor* q = out.dtype == DType::kFloat32 ? dequantized_from(graph, output) : nullptr;
  double lsb = 0;
  if (out.dtype == DType::kInt8) {
    lsb = out.quant.quantized() ? static_cast<double>(out.quant.scale[0]) : 1.0;
    c.rule = "1 LSB";
  } else if (q != nullptr) {
    lsb = static_cast<double>(q->quant.scale[0]);
    c.rule = "1 LSB of the dequantized int8 output";
  }
  if (lsb > 0) {
    c.tolerance = kInt8LsbTolerance * lsb * kLsbSlack;
    c.error_in_lsb = c.max_abs_error / lsb;
  } else {
    c.tolerance = kFloatRelTolerance * std::max(max_ref, 1e-30);
    c.rule = "1e-4 x max|reference|";
  }
  c.pass = c.max_abs_error <= c.tolerance;
  return c;
}

}  // namespace tlvlink::cli
