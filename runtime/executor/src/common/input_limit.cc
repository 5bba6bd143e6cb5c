// float_input_limit: the largest float input magnitude for which no float value in the graph can
// overflow float32 (executor.h). Interval bounds on |value|, tensor by tensor in topological
// order; a conv / FC output is bounded by max_c (sum_k |w_ck|) * |x| + max_c |b_c| before its
// activation, which also bounds every partial sum of the accumulation. Every bound is
// nondecreasing in the input bound, so the limit is found by bisection on its exponent.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "tlvlink/executor.h"

namespace tlvlink {
namespace {

// A bound is safe below half of FLT_MAX: rounding in a different summation order (XNNPACK's
// kernels) cannot then reach Inf.
constexpr double kSafe = static_cast<double>(FLT_MAX) / 2.0;

// |value| of an int8 tensor, dequantized: never more than scale x (255 + |zp| margin).
double int8_bound(const Tensor& t) {
  if (!t.quant.quantized()) return 128;
  double s = 0;
  for (float v : t.quant.scale) s = std::max(s, static_cast<double>(v));
  return s * 256.0;
}

double constant_bound(const Tensor& t) {
  if (t.dtype != DType::kFloat32) return int8_bound(t);
  double b = 0;
  const size_t n = t.data.size() / sizeof(float);
  for (size_t i = 0; i < n; ++i) {
    float v;
    std::memcpy(&v, t.data.data() + i * sizeof v, sizeof v);
    b = std::max(b, std::fabs(static_cast<double>(v)));
  }
  return b;
}

// Per operator: the gain and offset of a float conv / FC (max_c sum|w_c|, max|b|).
struct Linear {
  double gain = 0, offset = 0;
};

Linear linear_of(const Graph& g, const Operator& op) {
  Linear l;
  const Tensor& w = g.tensor(op.inputs[1]);
  const auto cout = static_cast<size_t>(w.shape[0]);
  const size_t per = w.shape.elements() / std::max<size_t>(cout, 1);
  for (size_t c = 0; c < cout; ++c) {
    double sum = 0;
    for (size_t k = 0; k < per; ++k) {
      float v;
      std::memcpy(&v, w.data.data() + (c * per + k) * sizeof v, sizeof v);
      sum += std::fabs(static_cast<double>(v));
    }
    l.gain = std::max(l.gain, sum);
  }
  if (op.input_count > 2 && op.inputs[2] != kNoTensor)
    l.offset = constant_bound(g.tensor(op.inputs[2]));
  return l;
}

double after_activation(double b, Activation a) {
  const double hi = std::max(std::fabs(static_cast<double>(activation_min(a))),
                             std::fabs(static_cast<double>(activation_max(a))));
  return std::min(b, hi);
}

Activation activation_of(const Operator& op) {
  if (const auto* p = std::get_if<Conv2DParams>(&op.params)) return p->activation;
  if (const auto* p = std::get_if<FullyConnectedParams>(&op.params)) return p->activation;
  if (const auto* p = std::get_if<BinaryParams>(&op.params)) return p->activation;
  return Activation::kNone;
}

// The largest bound of any float value computed (accumulations included) when every float
// graph input is bounded by `input`.
// `first_unsafe`: the first operator whose bound passes kSafe (-1: none).
double worst_bound(const Graph& g, const std::vector<Linear>& linear, double input,
                   std::vector<double>& bound, int32_t* first_unsafe = nullptr) {
  double worst = 0;
  for (size_t t = 0; t < g.tensors.size(); ++t) {
    const Tensor& tensor = g.tensors[t];
    bound[t] = tensor.is_constant()              ? constant_bound(tensor)
               : tensor.dtype == DType::kFloat32 ? input
                                                 : int8_bound(tensor);
  }
  for (size_t i = 0; i < g.operators.size(); ++i) {
    const Operator& op = g.operators[i];
    const Tensor& out = g.tensor(op.output);
    const double a = bound[static_cast<size_t>(op.inputs[0])];
    const double b = op.input_count > 1 && op.inputs[1] != kNoTensor
                         ? bound[static_cast<size_t>(op.inputs[1])]
                         : 0;
    double y = a;
    switch (op.type) {
      case OpType::kConv2D:
      case OpType::kFullyConnected: y = linear[i].gain * a + linear[i].offset; break;
      case OpType::kAdd: y = a + b; break;
      case OpType::kMul: y = a * b; break;
      case OpType::kClamp: {
        const auto& p = std::get<ClampParams>(op.params);
        y = std::min(a, std::max(std::fabs(static_cast<double>(p.min)),
                                 std::fabs(static_cast<double>(p.max))));
        break;
      }
      case OpType::kSigmoid: y = 1; break;
      case OpType::kPad:
        y = std::max(a, std::fabs(static_cast<double>(std::get<PadParams>(op.params).value)));
        break;
      default: break;  // pooling, reshape, resize, (de)quantize: no larger than their input
    }
    // Only arithmetic creates larger values, and it does so before a fused activation: a float
    // conv / FC / add / mul's result, and global average pooling's sum (H x W values). Moving,
    // clamping, interpolating, quantizing or a sigmoid cannot overflow.
    if (g.tensor(op.inputs[0]).dtype == DType::kFloat32) {
      const bool arithmetic = op.type == OpType::kConv2D || op.type == OpType::kFullyConnected ||
                              op.type == OpType::kAdd || op.type == OpType::kMul;
      if (arithmetic) worst = std::max(worst, y);
      if (op.type == OpType::kGlobalAveragePool) {
        const Shape& in = g.tensor(op.inputs[0]).shape;
        worst = std::max(
            worst, a * static_cast<double>(in.elements() / static_cast<size_t>(in[0] * in[3])));
      }
    }
    if (first_unsafe != nullptr && *first_unsafe < 0 && !(worst <= kSafe)) {
      *first_unsafe = static_cast<int32_t>(i);
    }
    y = after_activation(y, activation_of(op));
    if (out.dtype != DType::kFloat32) y = int8_bound(out);  // saturates: always finite
    bound[static_cast<size_t>(op.output)] = y;
  }
  return worst;
}

}  // namespace

FloatInputLimit float_input_limit(const Graph& g) {
  std::vector<Linear> linear(g.operators.size());
  for (size_t i = 0; i < g.operators.size(); ++i) {
    const Operator& op = g.operators[i];
    const bool float_linear = (op.type == OpType::kConv2D || op.type == OpType::kFullyConnected) &&
                              g.tensor(op.inputs[1]).dtype == DType::kFloat32;
    if (float_linear) linear[i] = linear_of(g, op);
  }
  std::vector<double> bound(g.tensors.size());
  FloatInputLimit limit;
  if (worst_bound(g, linear, static_cast<double>(FLT_MAX), bound) <= kSafe) return limit;
  double lo = -160, hi = 128;  // log2 of the input bound: safe at 2^lo, unsafe at 2^hi
  if (!(worst_bound(g, linear, 0, bound) <= kSafe)) {
    lo = -std::numeric_limits<double>::infinity();  // constants alone overflow
  } else {
    for (int k = 0; k < 60; ++k) {
      const double mid = (lo + hi) / 2;
      (worst_bound(g, linear, std::exp2(mid), bound) <= kSafe ? lo : hi) = mid;
    }
  }
  limit.limit = static_cast<float>(std::exp2(lo));
  worst_bound(g, linear, std::exp2(hi), bound, &limit.op);
  return limit;
}

Status check_float_input(std::span<const float> values, const FloatInputLimit& bound,
                         const Graph& graph, std::string_view what) {
  const float limit = bound.limit;
  // Branch-free: the largest |x| as bits (for non-negative floats, including Inf and NaN, bit
  // order is value order, NaN above Inf). Only a failing tensor is walked again.
  uint32_t worst = 0;
  const auto* bits = reinterpret_cast<const uint32_t*>(values.data());
  for (size_t i = 0; i < values.size(); ++i) worst = std::max(worst, bits[i] & 0x7fffffffu);
  uint32_t limit_bits;
  std::memcpy(&limit_bits, &limit, sizeof limit_bits);
  if (worst <= limit_bits) return Status();
  // NaN/Inf first, with the executors' one message for them (executor.h check_finite).
  TLV_TRY(check_finite(values, what));
  for (size_t i = 0; i < values.size(); ++i) {
    if (std::fabs(values[i]) > limit) {
      const std::string_view op =
          bound.op >= 0 ? graph.operators[static_cast<size_t>(bound.op)].name : std::string_view();
      return Error::make(ErrorCode::kNonFiniteValue,
                         "%.*s: element %zu of %zu is %g, beyond +-%g, the largest input with "
                         "which float32 cannot overflow to Inf/NaN (first at operator '%.*s')",
                         static_cast<int>(what.size()), what.data(), i, values.size(),
                         static_cast<double>(values[i]), static_cast<double>(limit),
                         static_cast<int>(op.size()), op.data());
    }
  }
  return Status();
}

}  // namespace tlvlink
