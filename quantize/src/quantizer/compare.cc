// Float vs quantized model, per layer (matched by tensor name) and at the embedding output.

#include "tlvlink/quantize/layer_error.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>
#include <unordered_map>

#include "tlvlink/quant_math.h"

namespace tlvlink::quantize {
namespace {

size_t embedding_output(const Model& m) {
  const auto e = static_cast<size_t>(std::max(m.metadata().embedding_output, 0));
  return e < m.graph().outputs.size() ? e : 0;
}

// Values of `t` as float (int8 dequantized with its per-tensor parameters) into `out`.
void as_floats(const Tensor& t, std::span<const std::byte> bytes, std::vector<float>& out) {
  const size_t n = t.shape.elements();
  out.resize(n);
  if (t.dtype == DType::kFloat32) {
    std::memcpy(out.data(), bytes.data(), n * sizeof(float));
    return;
  }
  const auto* q = reinterpret_cast<const int8_t*>(bytes.data());
  for (size_t i = 0; i < n; ++i)
    out[i] = dequantize_value(q[i], t.quant.scale[0], t.quant.zero_point[0]);
}

struct Match {
  int32_t fp32 = kNoTensor, quantized = kNoTensor;
  size_t layer = 0;
};

// Each float-model operator output that exists in the quantized graph. A float tensor made by a
// Dequantize stands for its int8 input (the int8 values are what the deployed model computes).
std::vector<Match> match_tensors(const Graph& f, const Graph& q, std::vector<TensorError>& layers) {
  std::unordered_map<std::string_view, int32_t> by_name;
  std::vector<int32_t> producer(q.tensors.size(), -1);
  for (size_t i = 0; i < q.tensors.size(); ++i)
    by_name.emplace(q.tensors[i].name, static_cast<int32_t>(i));
  for (size_t i = 0; i < q.operators.size(); ++i)
    producer[static_cast<size_t>(q.operators[i].output)] = static_cast<int32_t>(i);
  std::vector<Match> matches;
  for (const Operator& op : f.operators) {
    const Tensor& t = f.tensor(op.output);
    auto it = by_name.find(t.name);
    if (it == by_name.end()) continue;  // fused away
    int32_t qi = it->second;
    const int32_t p = producer[static_cast<size_t>(qi)];
    if (q.tensor(qi).dtype == DType::kFloat32 && p >= 0 &&
        q.operators[static_cast<size_t>(p)].type == OpType::kDequantize) {
      qi = q.operators[static_cast<size_t>(p)].inputs[0];
    }
    const Tensor& qt = q.tensor(qi);
    if (qt.dtype != DType::kFloat32 && qt.dtype != DType::kInt8) continue;
    TensorError e;
    e.tensor = std::string(t.name);
    e.op = std::string(op.name);
    e.type = op.type;
    e.dtype = qt.dtype;
    e.scale = qt.dtype == DType::kInt8 ? qt.quant.scale[0] : 0.0f;
    layers.push_back(std::move(e));
    matches.push_back({op.output, qi, layers.size() - 1});
  }
  return matches;
}

}  // namespace

void ErrorStats::add(std::span<const float> ref, std::span<const float> approx) {
  const size_t n = std::min(ref.size(), approx.size());
  for (size_t i = 0; i < n; ++i) {
    const auto r = static_cast<double>(ref[i]), a = static_cast<double>(approx[i]);
    ref_energy += r * r;
    approx_energy += a * a;
    dot += r * a;
    err_energy += (r - a) * (r - a);
    max_abs = std::max(max_abs, std::fabs(r - a));
  }
  count += n;
}

double ErrorStats::sqnr_db() const {
  if (err_energy <= 0) return std::numeric_limits<double>::infinity();
  if (ref_energy <= 0) return -std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(ref_energy / err_energy);
}

double ErrorStats::cosine() const {
  if (ref_energy <= 0 && approx_energy <= 0) return 1.0;
  if (ref_energy <= 0 || approx_energy <= 0) return 0.0;
  return dot / std::sqrt(ref_energy * approx_energy);
}

double ErrorStats::rmse() const {
  return count == 0 ? 0.0 : std::sqrt(err_energy / static_cast<double>(count));
}

double ModelError::mean_cosine() const {
  if (frame_cosine.empty()) return 0;
  double s = 0;
  for (double c : frame_cosine) s += c;
  return s / static_cast<double>(frame_cosine.size());
}

double ModelError::min_cosine() const {
  return frame_cosine.empty() ? 0 : *std::min_element(frame_cosine.begin(), frame_cosine.end());
}

Result<ModelError> compare_models(const Model& fp32, const Model& quantized,
                                  std::span<const std::vector<float>> frames,
                                  const CompareOptions& options) {
  const Graph& fg = fp32.graph();
  const Graph& qg = quantized.graph();
  ExecutorOptions fo, qo;
  fo.expose_all_tensors = qo.expose_all_tensors = options.per_layer;
  qo.threads = options.threads;
  TLV_ASSIGN_OR_RETURN(auto fe, make_reference_executor(fp32, fo));
  auto qe_result = make_executor(quantized, options.quantized_executor, qo);
  if (!qe_result.ok()) return qe_result.error().with_context("quantized model");
  std::unique_ptr<Executor> qe = std::move(qe_result).value();
  TLV_ENSURE(fe->input(0).size() == qe->input(0).size(), ErrorCode::kShapeMismatch,
             "input 0 is %zu bytes in the float model, %zu in the quantized one",
             fe->input(0).size(), qe->input(0).size());
  const int32_t fout = fg.outputs[embedding_output(fp32)];
  const int32_t qout = qg.outputs[embedding_output(quantized)];
  TLV_ENSURE(fg.tensor(fout).shape.elements() == qg.tensor(qout).shape.elements(),
             ErrorCode::kShapeMismatch, "embedding outputs differ in size (%zu vs %zu)",
             fg.tensor(fout).shape.elements(), qg.tensor(qout).shape.elements());
  for (size_t i = 1; i < fg.inputs.size(); ++i)
    std::memset(fe->input(i).data(), 0, fe->input(i).size());
  for (size_t i = 1; i < qg.inputs.size(); ++i)
    std::memset(qe->input(i).data(), 0, qe->input(i).size());

  ModelError result;
  const std::vector<Match> matches =
      options.per_layer ? match_tensors(fg, qg, result.layers) : std::vector<Match>{};
  std::vector<float> a, b;
  for (size_t n = 0; n < frames.size(); ++n) {
    TLV_ENSURE(frames[n].size() * sizeof(float) == fe->input(0).size(), ErrorCode::kShapeMismatch,
               "frame %zu has %zu floats, input 0 needs %zu", n, frames[n].size(),
               fe->input(0).size() / sizeof(float));
    std::memcpy(fe->input(0).data(), frames[n].data(), fe->input(0).size());
    std::memcpy(qe->input(0).data(), frames[n].data(), qe->input(0).size());
    if (Status s = fe->invoke(); !s.ok())
      return s.error().with_context("float model, frame %zu", n);
    if (Status s = qe->invoke(); !s.ok())
      return s.error().with_context("quantized model, frame %zu", n);
    for (const Match& m : matches) {
      TLV_ASSIGN_OR_RETURN(std::span<const std::byte> fb, fe->tensor(m.fp32));
      TLV_ASSIGN_OR_RETURN(std::span<const std::byte> qb, qe->tensor(m.quantized));
      as_floats(fg.tensor(m.fp32), fb, a);
      as_floats(qg.tensor(m.quantized), qb, b);
      result.layers[m.layer].error.add(a, b);
    }
    as_floats(fg.tensor(fout), fe->output(embedding_output(fp32)), a);
    as_floats(qg.tensor(qout), qe->output(embedding_output(quantized)), b);
    result.embedding.add(a, b);
    ErrorStats one;
    one.add(a, b);
    result.frame_cosine.push_back(one.cosine());
    ++result.frames;
    if (options.on_frame) options.on_frame(result.frames);
  }
  return result;
}

Result<std::vector<std::vector<float>>> embeddings(const Model& model,
                                                   std::span<const std::vector<float>> frames,
                                                   ExecutorKind kind, int threads) {
  ExecutorOptions eo;
  eo.threads = threads;
  TLV_ASSIGN_OR_RETURN(auto exec, make_executor(model, kind, eo));
  const Graph& g = model.graph();
  for (size_t i = 1; i < g.inputs.size(); ++i)
    std::memset(exec->input(i).data(), 0, exec->input(i).size());
  const size_t e = embedding_output(model);
  std::vector<std::vector<float>> out(frames.size());
  for (size_t n = 0; n < frames.size(); ++n) {
    TLV_ENSURE(frames[n].size() * sizeof(float) == exec->input(0).size(), ErrorCode::kShapeMismatch,
               "frame %zu has %zu floats, input 0 needs %zu", n, frames[n].size(),
               exec->input(0).size() / sizeof(float));
    std::memcpy(exec->input(0).data(), frames[n].data(), exec->input(0).size());
    if (Status s = exec->invoke(); !s.ok()) return s.error().with_context("frame %zu", n);
    as_floats(g.tensor(g.outputs[e]), exec->output(e), out[n]);
  }
  return out;
}

ModelError compare_embeddings(std::span<const std::vector<float>> reference,
                              std::span<const std::vector<float>> outputs) {
  ModelError result;
  for (size_t n = 0; n < std::min(reference.size(), outputs.size()); ++n) {
    result.embedding.add(reference[n], outputs[n]);
    ErrorStats one;
    one.add(reference[n], outputs[n]);
    result.frame_cosine.push_back(one.cosine());
    ++result.frames;
  }
  return result;
}

}  // namespace tlvlink::quantize
