// Embedder: one frame -> preprocess (the model's InputSpec) -> executor -> embedding floats.

#include <cstring>

#include "tlvlink/eval/embeddings.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/io/npy_image.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::eval {

Embedder::~Embedder() = default;

Result<std::unique_ptr<Embedder>> Embedder::create(const Model& model,
                                                   const EmbedderOptions& options) {
  const Graph& g = model.graph();
  const Metadata& m = model.metadata();
  TLV_ENSURE(g.inputs.size() == 1, ErrorCode::kModelUnsupported,
             "model has %zu inputs; the evaluator feeds one frame", g.inputs.size());
  const Tensor& in = g.tensor(g.inputs[0]);
  TLV_ENSURE(in.dtype == DType::kFloat32, ErrorCode::kModelUnsupported,
             "model input '%.*s' is %s; frames can only feed a float32 input",
             static_cast<int>(in.name.size()), in.name.data(), dtype_name(in.dtype));
  TLV_ENSURE(m.embedding_dim > 0, ErrorCode::kModelUnsupported,
             "model '%.*s' has no embedding output (metadata embedding_dim = %d)",
             static_cast<int>(m.name.size()), m.name.data(), m.embedding_dim);
  TLV_ENSURE(m.embedding_output >= 0 && static_cast<size_t>(m.embedding_output) < g.outputs.size(),
             ErrorCode::kModelUnsupported,
             "model has no embedding output: embedding_output = %d, graph has %zu outputs",
             m.embedding_output, g.outputs.size());
  const Tensor& out = g.tensor(g.outputs[static_cast<size_t>(m.embedding_output)]);
  TLV_ENSURE(
      out.shape.elements() == static_cast<size_t>(m.embedding_dim), ErrorCode::kModelUnsupported,
      "embedding output '%.*s' holds %zu values, metadata embedding_dim is %d",
      static_cast<int>(out.name.size()), out.name.data(), out.shape.elements(), m.embedding_dim);
  TLV_ENSURE(out.dtype == DType::kFloat32 ||
                 (out.dtype == DType::kInt8 && out.quant.quantized() && !out.quant.per_channel()),
             ErrorCode::kModelUnsupported,
             "embedding output '%.*s' is %s; float32 or quantized int8 expected",
             static_cast<int>(out.name.size()), out.name.data(), dtype_name(out.dtype));
  ExecutorOptions eo;
  eo.threads = options.threads;
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Executor> exec, make_executor(model, options.executor, eo));
  std::unique_ptr<Embedder> e(new Embedder());
  e->model_ = &model;
  e->exec_ = std::move(exec);
  e->dim_ = m.embedding_dim;
  return e;
}

Status Embedder::embed(const sim::RgbImage& frame, std::span<float> out) {
  TLV_ENSURE(out.size() == static_cast<size_t>(dim_), ErrorCode::kShapeMismatch,
             "embed: output span holds %zu floats, embedding has %d", out.size(), dim_);
  TLV_ENSURE(frame.height > 0 && frame.width > 0 &&
                 frame.rgb.size() ==
                     static_cast<size_t>(frame.height) * static_cast<size_t>(frame.width) * 3,
             ErrorCode::kShapeMismatch, "embed: frame %dx%d holds %zu bytes", frame.width,
             frame.height, frame.rgb.size());
  tools::Image image{frame.width, frame.height, 3, frame.rgb};
  TLV_ASSIGN_OR_RETURN(std::vector<float> x, image::preprocess(image, model_->metadata().input));
  std::span<std::byte> dst = exec_->input(0);
  TLV_ENSURE(x.size() * sizeof(float) == dst.size(), ErrorCode::kShapeMismatch,
             "preprocessing gave %zu values, the model input needs %zu", x.size(),
             dst.size() / sizeof(float));
  std::memcpy(dst.data(), x.data(), dst.size());
  TLV_TRY(exec_->invoke());
  const Metadata& m = model_->metadata();
  const size_t oi = static_cast<size_t>(m.embedding_output);
  const Tensor& t = model_->graph().tensor(model_->graph().outputs[oi]);
  const std::span<const std::byte> bytes = exec_->output(oi);
  if (t.dtype == DType::kFloat32) {
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(float));
  } else {
    const auto* q = reinterpret_cast<const int8_t*>(bytes.data());
    for (size_t i = 0; i < out.size(); ++i)
      out[i] = dequantize_value(q[i], t.quant.scale[0], t.quant.zero_point[0]);
  }
  return {};
}

std::span<const float> GraspEmbeddings::frame(size_t episode, int32_t finger,
                                              heads::Moment moment) const {
  const size_t d = static_cast<size_t>(dim);
  const size_t f = static_cast<size_t>(finger * heads::kMoments + static_cast<int32_t>(moment));
  return std::span<const float>(values).subspan((episode * kGraspFrames + f) * d, d);
}

std::span<const float> GraspEmbeddings::difference_of(size_t episode, int32_t finger) const {
  if (difference.empty()) return {};
  constexpr auto n = static_cast<size_t>(heads::kDifferenceFeatures);
  return std::span<const float>(difference)
      .subspan((episode * heads::kFingers + static_cast<size_t>(finger)) * n, n);
}

std::span<const float> GraspEmbeddings::feature(size_t episode, const heads::GraspFeature& f,
                                                int32_t finger_xor) const {
  const int32_t finger = f.finger ^ finger_xor;
  return f.kind == heads::FeatureKind::kDifference ? difference_of(episode, finger)
                                                   : frame(episode, finger, f.moment);
}

}  // namespace tlvlink::eval
