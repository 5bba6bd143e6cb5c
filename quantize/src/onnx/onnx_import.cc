// import_onnx: parse the ModelProto, check the opset, run the importer, write the metadata
// (input spec, embedding size, provenance) and prove the result loads.

#include "tlvlink/quantize/onnx_import.h"

#include <climits>
#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "onnx/onnx_internal.h"
#include "tlvlink/model.h"

namespace tlvlink::quantize {
namespace {

using onnx_internal::Importer;
using onnx_internal::Value;

Result<int64_t> default_opset(const onnx::ModelProto& model) {
  for (const onnx::OperatorSetIdProto& id : model.opset_import()) {
    if (id.domain().empty() || id.domain() == "ai.onnx") {
      const int64_t v = id.version();
      TLV_ENSURE(v >= kMinOnnxOpset && v <= kMaxOnnxOpset, ErrorCode::kModelUnsupported,
                 "the model uses ONNX opset %lld; tlvlink convert reads opsets %lld to %lld "
                 "(re-export with an opset in that range)",
                 static_cast<long long>(v), static_cast<long long>(kMinOnnxOpset),
                 static_cast<long long>(kMaxOnnxOpset));
      return v;
    }
  }
  return Error::make(ErrorCode::kFormat, "the model imports no default-domain (ai.onnx) opset");
}

// One value per channel from a user list (one value repeats); empty uses `fallback`.
Result<std::vector<float>> per_channel_option(const std::vector<float>& given, float fallback,
                                              int64_t channels, const char* what) {
  const auto c = static_cast<size_t>(channels);
  if (given.empty()) return std::vector<float>(c, fallback);
  TLV_ENSURE(given.size() == 1 || given.size() == c, ErrorCode::kInvalidArgument,
             "%s has %zu values for a %zu-channel input (give 1 or %zu)", what, given.size(), c, c);
  for (float v : given) {
    TLV_ENSURE(std::isfinite(v), ErrorCode::kInvalidArgument, "%s value %g is not finite", what,
               static_cast<double>(v));
  }
  return given.size() == 1 ? std::vector<float>(c, given[0]) : given;
}

Result<MetadataSpec> metadata_for(const Importer& imp, const onnx::ModelProto& model, int64_t opset,
                                  const OnnxImportOptions& o) {
  const Value& in = imp.values()[static_cast<size_t>(imp.input())];
  const int64_t channels = in.shape[1];
  MetadataSpec m;
  m.name = o.model_name;
  if (m.name.empty()) m.name = std::filesystem::path(o.source_name).stem().string();
  if (m.name.empty()) m.name = model.graph().name();
  m.input.height = static_cast<int32_t>(in.shape[2]);
  m.input.width = static_cast<int32_t>(in.shape[3]);
  m.input.channels = static_cast<int32_t>(channels);
  m.input.channel_order = channels == 1 ? ChannelOrder::kGray : ChannelOrder::kRGB;
  if (o.channel_order.has_value()) {
    const bool gray = *o.channel_order == ChannelOrder::kGray;
    TLV_ENSURE(gray == (channels == 1), ErrorCode::kInvalidArgument,
               "channel order %s does not fit a %lld-channel input", gray ? "gray" : "rgb/bgr",
               static_cast<long long>(channels));
    m.input.channel_order = *o.channel_order;
  }
  TLV_ASSIGN_OR_RETURN(m.input.mean, per_channel_option(o.mean, 0.0f, channels, "mean"));
  TLV_ASSIGN_OR_RETURN(m.input.std, per_channel_option(o.std, 1.0f, channels, "std"));
  for (float s : m.input.std) {
    TLV_ENSURE(s > 0.0f, ErrorCode::kInvalidArgument, "std %g must be positive",
               static_cast<double>(s));
  }
  const Value& out = imp.values()[static_cast<size_t>(imp.outputs()[0])];
  m.embedding_dim = static_cast<int32_t>(onnx_internal::element_count(out.shape));
  m.embedding_output = 0;
  m.producer = "tlvlink convert";
  nlohmann::json training = {
      {"kind", "onnx-import"},
      {"source", o.source_name},
      {"opset", opset},
      {"onnx_ir_version", model.ir_version()},
      {"onnx_producer", model.producer_name() + " " + model.producer_version()},
      {"onnx_graph", model.graph().name()},
      {"layout", "NCHW converted to NHWC; 4-D outputs are NHWC"}};
  // Strings from the file may be any bytes: invalid UTF-8 is replaced, never thrown on.
  m.training_json = training.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  m.quantization_json = nlohmann::json{{"kind", "none"}, {"dtype", "float32"}}.dump();
  return m;
}

}  // namespace

Result<OnnxImportResult> import_onnx(std::span<const std::byte> onnx_bytes,
                                     const OnnxImportOptions& options) {
  TLV_ENSURE(!onnx_bytes.empty(), ErrorCode::kFormat, "the ONNX file is empty");
  TLV_ENSURE(onnx_bytes.size() < static_cast<size_t>(INT_MAX), ErrorCode::kFormat,
             "the ONNX file is larger than protobuf's 2 GB limit");
  onnx::ModelProto model;
  TLV_ENSURE(model.ParseFromArray(onnx_bytes.data(), static_cast<int>(onnx_bytes.size())),
             ErrorCode::kFormat,
             "not a readable ONNX model: protobuf parsing failed (%zu bytes; truncated or "
             "corrupt file?)",
             onnx_bytes.size());
  TLV_ENSURE(model.has_graph() && model.graph().node_size() > 0, ErrorCode::kFormat,
             "not a readable ONNX model: no graph or no nodes (truncated or not ONNX?)");
  TLV_ASSIGN_OR_RETURN(const int64_t opset, default_opset(model));

  Importer imp(model.graph(), opset);
  TLV_TRY(imp.run());
  TLV_ASSIGN_OR_RETURN(const MetadataSpec metadata, metadata_for(imp, model, opset, options));

  OnnxImportResult r;
  OnnxImportSummary& s = r.summary;
  s.opset = opset;
  s.onnx_producer = model.producer_name() + " " + model.producer_version();
  s.onnx_nodes = static_cast<size_t>(model.graph().node_size());
  s.fused = imp.fused();
  s.input_shape = onnx_internal::stored_shape(imp.values()[static_cast<size_t>(imp.input())]);
  s.output_shape = onnx_internal::stored_shape(imp.values()[static_cast<size_t>(imp.outputs()[0])]);
  TLV_ASSIGN_OR_RETURN(r.model, onnx_internal::emit_model(imp, metadata, s.operators));

  // The writer does not validate; the loader does. A model that does not load is our bug.
  auto loaded = Model::load(r.model);
  if (!loaded.ok()) {
    return loaded.error().with_context("the converted model does not load (a converter bug)");
  }
  return r;
}

}  // namespace tlvlink::quantize
