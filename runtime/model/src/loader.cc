// Model::load: size limits -> integrity trailer and hash (and signature, when a key is given)
// -> aligned copy -> identifier -> flatbuffers Verifier -> version -> tensors -> operators ->
// topology -> per-op semantics -> no dead operator -> metadata (-> legacy checksum, for a
// file without a trailer accepted by `tlvlink upgrade`).

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <vector>

#include "model_internal.h"
#include "tlvlink/model.h"

namespace tlvlink {

using model_internal::Buffers;

void Model::AlignedFree::operator()(std::byte* p) const { std::free(p); }

namespace {

constexpr size_t kAlignment = 16;  // constant data is used in place by the kernels

// Activations are int8 per-tensor (quantization.md): the reference kernels read scale[0] and an
// XNNPACK qint8 value has one scale, so a per-channel activation would run with wrong numbers on
// one executor and be refused by the other. Only Conv2D / FullyConnected weights and bias may be
// per-channel. Checked here, for every operand of every operator before its family validator
// reads scale[0], rather than op by op (Conv2D / FC once let a per-channel input through).
Status check_activation_quantization(const Graph& graph, size_t op_index) {
  const Operator& op = graph.operators[op_index];
  const bool has_weights = op.type == OpType::kConv2D || op.type == OpType::kFullyConnected;
  const size_t activation_inputs = has_weights ? 1 : op.input_count;
  for (size_t k = 0; k <= activation_inputs; ++k) {
    const int32_t t = k < activation_inputs ? op.inputs[k] : op.output;
    if (t == kNoTensor) continue;
    const QuantParams& q = graph.tensor(t).quant;
    TLV_ENSURE(!q.per_channel(), ErrorCode::kModelInvalidOperator,
               "%s: %s %s is quantized per-channel (%zu scales along axis %d); activations "
               "must be quantized per-tensor",
               model_internal::op_label(graph, op_index).text,
               k < activation_inputs ? "input" : "output",
               model_internal::tensor_label(graph, t).text, q.scale.size(), q.axis);
  }
  return {};
}

// Every operator's result is read by a later operator or is a graph output. Neither the
// converter nor the quantizer writes a dead operator (one is a sign of a damaged file); it would
// cost time every frame, and XNNPACK (2022) drops the unread value but keeps the node writing
// it, then asserts when creating the runtime (found by the loader fuzzer). Checked after the
// per-operator validators, so a malformed operator still gets its own error.
Status check_outputs_used(const Graph& graph) {
  std::vector<bool> used(graph.tensors.size(), false);
  for (int32_t t : graph.outputs) used[static_cast<size_t>(t)] = true;
  for (const Operator& op : graph.operators) {
    for (size_t k = 0; k < op.input_count; ++k) {
      if (op.inputs[k] != kNoTensor) used[static_cast<size_t>(op.inputs[k])] = true;
    }
  }
  for (size_t i = 0; i < graph.operators.size(); ++i) {
    const int32_t out = graph.operators[i].output;
    TLV_ENSURE(used[static_cast<size_t>(out)], ErrorCode::kModelInvalidOperator,
               "%s writes %s, which no operator reads and which is not a graph output",
               model_internal::op_label(graph, i).text,
               model_internal::tensor_label(graph, out).text);
  }
  return {};
}

Status validate_operators(const Graph& graph) {
  for (size_t i = 0; i < graph.operators.size(); ++i) {
    TLV_TRY(check_activation_quantization(graph, i));
    switch (graph.operators[i].type) {
      case OpType::kConv2D:
      case OpType::kFullyConnected: TLV_TRY(model_internal::validate_conv_fc(graph, i)); break;
      case OpType::kAdd:
      case OpType::kMul:
      case OpType::kClamp:
      case OpType::kSigmoid:
      case OpType::kQuantize:
      case OpType::kDequantize: TLV_TRY(model_internal::validate_elementwise(graph, i)); break;
      default: TLV_TRY(model_internal::validate_shaping(graph, i)); break;
    }
  }
  // Inputs that some operator reads were checked with that operator (whose name is the better
  // clue); this catches the ones none reads.
  for (int32_t t : graph.inputs) {
    const QuantParams& q = graph.tensor(t).quant;
    TLV_ENSURE(!q.per_channel(), ErrorCode::kModelInvalidTensor,
               "graph input %s is quantized per-channel (%zu scales along axis %d); activations "
               "must be quantized per-tensor",
               model_internal::tensor_label(graph, t).text, q.scale.size(), q.axis);
  }
  return {};
}

}  // namespace

Result<std::unique_ptr<Model>> Model::with_buffer(size_t size) {
  std::unique_ptr<Model> model(new (std::nothrow) Model());
  TLV_ENSURE(model != nullptr, ErrorCode::kOutOfMemory, "allocating the model");
  const size_t padded = (size + kAlignment - 1) / kAlignment * kAlignment;
  model->data_.reset(static_cast<std::byte*>(std::aligned_alloc(kAlignment, padded)));
  TLV_ENSURE(model->data_ != nullptr, ErrorCode::kOutOfMemory, "allocating %zu bytes for the model",
             padded);
  std::memset(model->data_.get() + size, 0, padded - size);
  model->size_ = size;
  return model;
}

Result<std::unique_ptr<Model>> Model::load(std::span<const std::byte> bytes,
                                           const LoadOptions& options) {
  TLV_ENSURE(bytes.size() >= 8, ErrorCode::kModelMalformed,
             "model file is %zu bytes: too short to be a tlvlink model", bytes.size());
  TLV_ENSURE(bytes.size() <= kMaxModelBytes, ErrorCode::kModelMalformed,
             "model file is %zu bytes, over the %zu-byte limit", bytes.size(), kMaxModelBytes);
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Model> model, with_buffer(bytes.size()));
  std::memcpy(model->data_.get(), bytes.data(), bytes.size());
  return parse(std::move(model), options);
}

// The model's own aligned copy is checked and parsed in place: nothing is parsed before the
// integrity check, and load_file reads the file straight into that copy (one copy in memory).
Result<std::unique_ptr<Model>> Model::parse(std::unique_ptr<Model> model,
                                            const LoadOptions& options) {
  const std::span<const std::byte> bytes = model->bytes();
  // Integrity first: nothing of an altered file is parsed. A file without a trailer is read
  // whole only when asked to (upgrade, or fuzzing with verify_checksum off).
  ModelIntegrity integrity;
  integrity.body_size = bytes.size();
  // A file that is no model at all gets "not a tlvlink model", not advice on upgrading.
  if (!has_integrity_trailer(bytes) &&
      !fb::ModelBufferHasIdentifier(reinterpret_cast<const uint8_t*>(bytes.data()))) {
    return model_internal::check_identifier(reinterpret_cast<const uint8_t*>(bytes.data())).error();
  }
  const bool legacy =
      !has_integrity_trailer(bytes) && (options.accept_legacy || !options.verify_checksum);
  if (!legacy) {
    TLV_ASSIGN_OR_RETURN(integrity, read_integrity(bytes, options.verify_checksum));
  }
  if (options.public_key != nullptr) {
    TLV_ENSURE(!legacy, ErrorCode::kModelSignature,
               "the model has no integrity trailer, so no signature; a signed model is required");
    TLV_TRY(check_signature(integrity, *options.public_key));
  }

  model->integrity_ = integrity;
  const auto* raw = reinterpret_cast<const uint8_t*>(model->data_.get());
  const size_t body_size = integrity.body_size;  // the flatbuffer, without the trailer
  TLV_ENSURE(body_size >= 8, ErrorCode::kModelMalformed,
             "model file holds %zu bytes before its trailer: too short to be a tlvlink model",
             body_size);

  TLV_TRY(model_internal::check_identifier(raw));
  flatbuffers::Verifier verifier(raw, body_size, /*max_depth=*/64,
                                 /*max_tables=*/4 * (kMaxTensors + kMaxOperators));
  TLV_ENSURE(fb::VerifyModelBuffer(verifier), ErrorCode::kModelMalformed,
             "flatbuffers verification failed: the file is truncated or corrupt "
             "(a table or vector points outside the %zu-byte flatbuffer)",
             body_size);

  const fb::Model* root = fb::GetModel(raw);
  model->schema_version_ = root->schema_version();
  TLV_ENSURE(root->schema_version() == kSchemaVersion, ErrorCode::kModelVersion,
             "model schema version %u, this runtime reads version %u", root->schema_version(),
             kSchemaVersion);
  TLV_ENSURE(root->graph() != nullptr, ErrorCode::kModelMalformed, "model has no graph");

  // Buffer 0 is the empty "no data" buffer; every other buffer must be 16-byte aligned.
  std::vector<std::span<const std::byte>> buffers;
  if (root->buffers() != nullptr) {
    buffers.reserve(root->buffers()->size());
    for (flatbuffers::uoffset_t i = 0; i < root->buffers()->size(); ++i) {
      const fb::Buffer* b = root->buffers()->Get(i);
      if (b == nullptr || b->data() == nullptr || b->data()->size() == 0) {
        buffers.emplace_back();
        continue;
      }
      const auto* p = reinterpret_cast<const std::byte*>(b->data()->data());
      TLV_ENSURE(reinterpret_cast<uintptr_t>(p) % kAlignment == 0, ErrorCode::kModelMalformed,
                 "buffer %u is not %zu-byte aligned", i, kAlignment);
      buffers.emplace_back(p, b->data()->size());
    }
  }
  TLV_ENSURE(buffers.empty() || buffers[0].empty(), ErrorCode::kModelMalformed,
             "buffer 0 must be empty (it means 'no data'), it holds %zu bytes", buffers[0].size());

  const Buffers buffer_view(buffers);
  Graph& graph = model->graph_;
  TLV_TRY(model_internal::convert_tensors(*root->graph(), buffer_view, graph));
  TLV_TRY(model_internal::convert_operators(*root->graph(), graph));
  TLV_TRY(model_internal::validate_topology(*root->graph(), graph));
  TLV_TRY(validate_operators(graph));
  TLV_TRY(check_outputs_used(graph));
  TLV_TRY(model_internal::convert_metadata(root->metadata(), buffer_view, graph, model->metadata_));

  if (legacy && options.verify_checksum) {
    const uint64_t expected = model->metadata_.provenance.content_checksum;
    const uint64_t actual = content_checksum(buffer_view);
    TLV_ENSURE(expected == actual, ErrorCode::kModelChecksum,
               "legacy file: constant data checksum is %016llx, the file records %016llx: "
               "weights were modified or corrupted after the model was written",
               static_cast<unsigned long long>(actual), static_cast<unsigned long long>(expected));
  }
  return model;
}

}  // namespace tlvlink
