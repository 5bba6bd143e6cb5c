#include "tlvlink/quantize/model_builder.h"

#include "tlvlink/model.h"
#include "tlvlink/model_integrity.h"
#include "tlvlink/verify/golden_heads.h"
#include "writer_internal.h"

namespace tlvlink::quantize {

using writer_internal::GoldenIndices;

QuantSpec QuantSpec::per_channel(std::vector<float> scales, int32_t axis) {
  std::vector<int32_t> zero_points(scales.size(), 0);
  return {std::move(scales), std::move(zero_points), axis};
}

int32_t ModelBuilder::add_activation(std::string name, DType dtype, std::vector<int32_t> shape,
                                     QuantSpec quant) {
  tensors_.push_back({std::move(name), dtype, std::move(shape), std::move(quant), 0});
  return static_cast<int32_t>(tensors_.size() - 1);
}

int32_t ModelBuilder::add_constant_bytes(std::string name, DType dtype, std::vector<int32_t> shape,
                                         std::span<const std::byte> data, QuantSpec quant) {
  buffers_.emplace_back(data.begin(), data.end());
  const auto buffer = static_cast<uint32_t>(buffers_.size() - 1);
  tensors_.push_back({std::move(name), dtype, std::move(shape), std::move(quant), buffer});
  return static_cast<int32_t>(tensors_.size() - 1);
}

void ModelBuilder::add_op(OpType type, std::string name, std::vector<int32_t> inputs,
                          int32_t output, OpParams params) {
  // Trailing absent optional inputs are dropped (a conv without bias has two inputs).
  while (inputs.size() > 2 && inputs.back() == kNoTensor) inputs.pop_back();
  ops_.push_back({type, std::move(name), std::move(inputs), output, std::move(params)});
}

std::vector<std::byte> ModelBuilder::finish() const {
  std::vector<std::byte> body = serialize(nullptr);
  // Golden head outputs come from the runtime's own code run on the written file, so what is
  // stored and what `verify` recomputes cannot mean different things. A file the loader refuses
  // (tests write those on purpose) gets none.
  if (!metadata_.golden.empty()) {
    auto model = Model::load(body, {.verify_checksum = false});
    if (model.ok() && verify::golden_heads_apply(**model)) {
      auto heads = verify::golden_head_outputs(**model);
      if (heads.ok()) body = serialize(&*heads);
    }
  }
  return seal_model(body);
}

std::vector<std::byte> ModelBuilder::serialize(const verify::GoldenHeadOutputs* heads) const {
  // Golden pairs are stored as constant buffers so the checksum covers them too.
  std::vector<std::vector<std::byte>> buffers = buffers_;
  std::vector<GoldenIndices> golden;
  for (const auto& [in, out] : metadata_.golden) {
    buffers.push_back(in);
    buffers.push_back(out);
    golden.push_back(
        {static_cast<uint32_t>(buffers.size() - 2), static_cast<uint32_t>(buffers.size() - 1)});
  }
  std::vector<std::span<const std::byte>> views(buffers.begin(), buffers.end());
  const uint64_t checksum = has_checksum_override_ ? checksum_override_ : content_checksum(views);

  flatbuffers::FlatBufferBuilder fbb(1 << 16);
  std::vector<flatbuffers::Offset<fb::Buffer>> fb_buffers;
  for (const auto& b : buffers) {
    fbb.ForceVectorAlignment(b.size(), 1, 16);
    auto data = fbb.CreateVector(reinterpret_cast<const uint8_t*>(b.data()), b.size());
    fb_buffers.push_back(fb::CreateBuffer(fbb, data));
  }
  std::vector<flatbuffers::Offset<fb::Tensor>> fb_tensors;
  for (const auto& t : tensors_) {
    flatbuffers::Offset<fb::Quantization> q = 0;
    if (!t.quant.scale.empty() || !t.quant.zero_point.empty()) {
      q = fb::CreateQuantization(fbb, fbb.CreateVector(t.quant.scale),
                                 fbb.CreateVector(t.quant.zero_point), t.quant.axis);
    }
    fb_tensors.push_back(fb::CreateTensor(fbb, fbb.CreateString(t.name),
                                          static_cast<fb::DType>(t.dtype),
                                          fbb.CreateVector(t.shape), q, t.buffer));
  }
  std::vector<flatbuffers::Offset<fb::Operator>> fb_ops;
  for (const auto& op : ops_) {
    size_t input_rank = 0;
    if (!op.inputs.empty() && op.inputs[0] >= 0 &&
        static_cast<size_t>(op.inputs[0]) < tensors_.size()) {
      input_rank = tensors_[static_cast<size_t>(op.inputs[0])].shape.size();
    }
    const auto [options_type, options] =
        writer_internal::write_options(fbb, op.type, op.params, input_rank);
    const std::vector<int32_t> outputs{op.output};
    fb_ops.push_back(fb::CreateOperator(fbb, static_cast<fb::OpType>(op.type),
                                        fbb.CreateString(op.name), fbb.CreateVector(op.inputs),
                                        fbb.CreateVector(outputs), options_type, options));
  }
  auto graph = fb::CreateGraph(fbb, fbb.CreateVector(fb_tensors), fbb.CreateVector(fb_ops),
                               fbb.CreateVector(inputs_), fbb.CreateVector(outputs_));
  auto metadata = writer_internal::write_metadata(fbb, metadata_, golden, heads, checksum);
  auto model = fb::CreateModel(fbb, schema_version_, graph, metadata, fbb.CreateVector(fb_buffers));
  fb::FinishModelBuffer(fbb, model);
  const auto* p = reinterpret_cast<const std::byte*>(fbb.GetBufferPointer());
  return {p, p + fbb.GetSize()};
}

}  // namespace tlvlink::quantize
