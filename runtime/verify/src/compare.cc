#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "tlvlink/quant_math.h"
#include "tlvlink/verify/compare.h"

namespace tlvlink::verify {
namespace {

// The quantized tensor a float graph output is dequantized from, if any.
const Tensor* dequantized_from(const Graph& g, int32_t output) {
  for (const Operator& op : g.operators) {
    if (op.output == output && op.type == OpType::kDequantize) return &g.tensor(op.inputs[0]);
  }
  return nullptr;
}

template <typename Get>
OutputComparison compare(const Graph& graph, int32_t output, size_t got_n, size_t want_n,
                         Get value) {
  OutputComparison c;
  double max_ref = 0;
  for (size_t k = 0; k < got_n && k < want_n; ++k) {
    const auto [gf, wf] = value(k);
    const double g = static_cast<double>(gf), w = static_cast<double>(wf);
    // A NaN anywhere must fail, never compare as "not greater".
    c.max_abs_error = std::isfinite(g - w) ? std::max(c.max_abs_error, std::fabs(g - w))
                                           : std::numeric_limits<double>::infinity();
    max_ref = std::max(max_ref, std::fabs(w));
  }
  if (got_n != want_n) c.max_abs_error = std::numeric_limits<double>::infinity();
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

}  // namespace

float output_value(const Tensor& t, std::span<const std::byte> bytes, size_t i) {
  switch (t.dtype) {
    case DType::kFloat32: {
      float f;
      std::memcpy(&f, bytes.data() + i * sizeof(float), sizeof f);
      return f;
    }
    case DType::kInt8: {
      const auto q = static_cast<int8_t>(bytes[i]);
      return t.quant.quantized() ? dequantize_value(q, t.quant.scale[0], t.quant.zero_point[0])
                                 : static_cast<float>(q);
    }
    case DType::kInt32: {
      int32_t v;
      std::memcpy(&v, bytes.data() + i * sizeof v, sizeof v);
      return static_cast<float>(v);
    }
    case DType::kUInt8: return static_cast<float>(static_cast<uint8_t>(bytes[i]));
  }
  return 0;
}

OutputComparison compare_output(const Graph& graph, int32_t output, std::span<const float> got,
                                std::span<const float> want) {
  return compare(graph, output, got.size(), want.size(), [&](size_t k) {
    return std::pair{got[k], want[k]};
  });
}

OutputComparison compare_output_bytes(const Graph& graph, int32_t output,
                                      std::span<const std::byte> got,
                                      std::span<const std::byte> want) {
  const Tensor& t = graph.tensor(output);
  const size_t size = dtype_size(t.dtype);
  return compare(graph, output, got.size() / size, want.size() / size, [&](size_t k) {
    return std::pair{output_value(t, got, k), output_value(t, want, k)};
  });
}

}  // namespace tlvlink::verify
