// Float graph -> int8 graph (see calibrate.h for the scheme). One pass over the operators in
// topological order; each float activation gets an int8 twin with calibrated parameters.

#include <algorithm>
#include <climits>
#include <cmath>
#include <string>

#include "tlvlink/quant_math.h"
#include "tlvlink/quantize/calibrate.h"

namespace tlvlink::quantize {
namespace {

std::vector<int32_t> dims_of(const Shape& s) {
  return {s.dims.begin(), s.dims.begin() + s.rank};
}

std::span<const float> floats_of(const Tensor& t) {
  return {reinterpret_cast<const float*>(t.data.data()), t.data.size() / sizeof(float)};
}

class Converter {
 public:
  Converter(const Model& m, std::span<const TensorRange> ranges, const Int8ConversionOptions& o)
      : g_(m.graph()),
        ranges_(ranges),
        opt_(o),
        map_(g_.tensors.size(), kNoTensor),
        quant_(g_.tensors.size()) {}

  Result<ModelBuilder> run(const Metadata& metadata) {
    TLV_ENSURE(ranges_.size() == g_.tensors.size(), ErrorCode::kInvalidArgument,
               "%zu ranges for %zu tensors", ranges_.size(), g_.tensors.size());
    std::vector<int32_t> inputs, outputs;
    for (int32_t in : g_.inputs) {
      const Tensor& t = g_.tensor(in);
      TLV_ENSURE(t.dtype == DType::kFloat32, ErrorCode::kModelUnsupported,
                 "graph input '%.*s' is %s; the converter expects float inputs",
                 static_cast<int>(t.name.size()), t.name.data(), dtype_name(t.dtype));
      const int32_t f = b_.add_activation(std::string(t.name), DType::kFloat32, dims_of(t.shape));
      TLV_TRY(define_activation(in, ".q"));
      b_.add_op(OpType::kQuantize, "quantize." + std::string(t.name), {f},
                map_[static_cast<size_t>(in)]);
      inputs.push_back(f);
    }
    for (const Operator& op : g_.operators) TLV_TRY(convert(op));
    for (int32_t out : g_.outputs) {
      const Tensor& t = g_.tensor(out);
      const int32_t f = b_.add_activation(std::string(t.name), DType::kFloat32, dims_of(t.shape));
      b_.add_op(OpType::kDequantize, "dequantize." + std::string(t.name),
                {map_[static_cast<size_t>(out)]}, f);
      outputs.push_back(f);
    }
    b_.set_inputs(inputs);
    b_.set_outputs(outputs);
    b_.metadata() = metadata_spec_from(metadata);
    b_.metadata().golden.clear();
    b_.metadata().quantization_json = opt_.quantization_json;
    return std::move(b_);
  }

 private:
  bool is_output(int32_t t) const {
    return std::find(g_.outputs.begin(), g_.outputs.end(), t) != g_.outputs.end();
  }

  // The int8 twin of activation `t`, with calibrated params (or `shared` ones for pass-through).
  Status define_activation(int32_t t, const char* suffix = "", const QuantSpec* shared = nullptr) {
    const Tensor& tensor = g_.tensor(t);
    const TensorRange& r = ranges_[static_cast<size_t>(t)];
    QuantSpec q;
    if (shared != nullptr) {
      q = *shared;
    } else {
      TLV_ENSURE(r.observed() && std::isfinite(r.min) && std::isfinite(r.max),
                 ErrorCode::kInvalidArgument, "tensor '%.*s' has no finite calibration range",
                 static_cast<int>(tensor.name.size()), tensor.name.data());
      q = activation_quant(r.min, r.max, opt_.min_activation_range);
    }
    std::string name(tensor.name);
    if (is_output(t) && *suffix == '\0') suffix = ".q";  // the float output keeps the plain name
    quant_[static_cast<size_t>(t)] = q;
    map_[static_cast<size_t>(t)] =
        b_.add_activation(name + suffix, DType::kInt8, dims_of(tensor.shape), q);
    return {};
  }

  // A float constant operand of Add/Mul: per-tensor asymmetric from its own values.
  int32_t constant_operand(int32_t t) {
    const Tensor& tensor = g_.tensor(t);
    const std::span<const float> v = floats_of(tensor);
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    const QuantSpec q = activation_quant(*lo, *hi, opt_.min_activation_range);
    std::vector<int8_t> data(v.size());
    for (size_t i = 0; i < v.size(); ++i)
      data[i] = quantize_value(v[i], q.scale[0], q.zero_point[0]);
    quant_[static_cast<size_t>(t)] = q;
    return b_.add_constant<int8_t>(std::string(tensor.name), dims_of(tensor.shape), data, q);
  }

  int32_t operand(int32_t t) {
    if (map_[static_cast<size_t>(t)] == kNoTensor && g_.tensor(t).is_constant()) {
      map_[static_cast<size_t>(t)] = constant_operand(t);
    }
    return map_[static_cast<size_t>(t)];
  }

  // Per-channel symmetric weights (axis 0) and an int32 bias at scale s_in * s_w[c].
  void conv_fc(const Operator& op) {
    const Tensor& w = g_.tensor(op.inputs[1]);
    const std::span<const float> wf = floats_of(w);
    const auto cout = static_cast<size_t>(w.shape[0]);
    const size_t per = wf.size() / cout;
    std::vector<int8_t> wq(wf.size());
    std::vector<float> scales(cout);
    for (size_t c = 0; c < cout; ++c) {
      float max_abs = 0;
      for (size_t i = 0; i < per; ++i) max_abs = std::max(max_abs, std::fabs(wf[c * per + i]));
      scales[c] = std::max(max_abs / static_cast<float>(kInt8Max), kMinWeightScale);
      for (size_t i = 0; i < per; ++i) {
        wq[c * per + i] =
            saturate_int8(round_half_even(wf[c * per + i] / scales[c]), kWeightMin, kInt8Max);
      }
    }
    const int32_t in = map_[static_cast<size_t>(op.inputs[0])];
    const float s_in = quant_[static_cast<size_t>(op.inputs[0])].scale[0];
    const int32_t wt = b_.add_constant<int8_t>(std::string(w.name), dims_of(w.shape), wq,
                                               QuantSpec::per_channel(scales, 0));
    int32_t bt = kNoTensor;
    if (op.inputs[2] != kNoTensor) {
      const Tensor& bias = g_.tensor(op.inputs[2]);
      const std::span<const float> bf = floats_of(bias);
      std::vector<int32_t> bq(cout);
      std::vector<float> bscales(cout);
      for (size_t c = 0; c < cout; ++c) {
        const double s = static_cast<double>(s_in) * static_cast<double>(scales[c]);
        bscales[c] = static_cast<float>(s);
        bq[c] = static_cast<int32_t>(std::clamp<double>(
            std::nearbyint(static_cast<double>(bf[c]) / s), INT32_MIN, INT32_MAX));
      }
      bt = b_.add_constant<int32_t>(std::string(bias.name), dims_of(bias.shape), bq,
                                    QuantSpec::per_channel(bscales, 0));
    }
    b_.add_op(op.type, std::string(op.name), {in, wt, bt}, map_[static_cast<size_t>(op.output)],
              op.params);
  }

  Status convert(const Operator& op) {
    const std::string name(op.name);
    const int32_t x = op.inputs[0];
    switch (op.type) {
      case OpType::kConv2D:
      case OpType::kFullyConnected:
        TLV_TRY(define_activation(op.output));
        conv_fc(op);
        return {};
      case OpType::kAdd:
      case OpType::kMul: {
        const int32_t a = operand(op.inputs[0]), c = operand(op.inputs[1]);
        TLV_TRY(define_activation(op.output));
        b_.add_op(op.type, name, {a, c}, map_[static_cast<size_t>(op.output)], op.params);
        return {};
      }
      case OpType::kGlobalAveragePool: TLV_TRY(define_activation(op.output)); break;
      case OpType::kSigmoid: {
        const QuantSpec fixed = QuantSpec::per_tensor(1.0f / 256.0f, -128);
        TLV_TRY(define_activation(op.output, "", &fixed));
        break;
      }
      case OpType::kClamp:
      case OpType::kMaxPool2D:
      case OpType::kPad:
      case OpType::kReshape:
      case OpType::kResizeBilinear: {
        const QuantSpec shared = quant_[static_cast<size_t>(x)];
        TLV_TRY(define_activation(op.output, "", &shared));
        break;
      }
      case OpType::kQuantize:
      case OpType::kDequantize:
        return Error::make(ErrorCode::kModelUnsupported,
                           "operator '%s' (%s): the model is already (partly) quantized",
                           name.c_str(), op_type_name(op.type));
    }
    b_.add_op(op.type, name, {operand(x)}, map_[static_cast<size_t>(op.output)], op.params);
    return {};
  }

  const Graph& g_;
  std::span<const TensorRange> ranges_;
  const Int8ConversionOptions& opt_;
  ModelBuilder b_;
  std::vector<int32_t> map_;      // float tensor -> int8 tensor in b_
  std::vector<QuantSpec> quant_;  // params given to each mapped tensor
};

}  // namespace

Result<ModelBuilder> convert_to_int8(const Model& fp32, std::span<const TensorRange> ranges,
                                     const Int8ConversionOptions& options) {
  return Converter(fp32, ranges, options).run(fp32.metadata());
}

}  // namespace tlvlink::quantize
