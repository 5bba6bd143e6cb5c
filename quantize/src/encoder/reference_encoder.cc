// build_reference_encoder: float graph -> load (validate) -> [calibrate + convert to int8] ->
// golden pairs from the reference executor.

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "encoder/encoder_internal.h"
#include "tlvlink/log.h"
#include "tlvlink/quantize/calibrate.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink::quantize {
namespace {

TLV_LOG_CATEGORY(kLogQuantize, "quantize");

using encoder_internal::derive_seed;

// Frames are made larger than the model input so preprocessing really resizes, as on a sensor.
int32_t frame_side(int32_t resolution) { return resolution + resolution / 4; }

Result<std::vector<std::vector<float>>> make_inputs(const ReferenceEncoderOptions& o,
                                                    const InputSpec& spec, int32_t count,
                                                    uint64_t stream) {
  std::vector<std::vector<float>> inputs;
  const int32_t side = frame_side(o.resolution);
  for (int32_t i = 0; i < count; ++i) {
    const std::vector<uint8_t> frame =
        synthetic_touch_frame(side, side, derive_seed(o.seed, stream + static_cast<uint64_t>(i)));
    TLV_ASSIGN_OR_RETURN(std::vector<float> x, o.preprocess(frame, side, side, spec));
    inputs.push_back(std::move(x));
  }
  return inputs;
}

Status check_options(const ReferenceEncoderOptions& o) {
  TLV_ENSURE(o.resolution >= kMinEncoderResolution && o.resolution <= kMaxEncoderResolution,
             ErrorCode::kInvalidArgument, "resolution %d outside %d..%d", o.resolution,
             kMinEncoderResolution, kMaxEncoderResolution);
  TLV_ENSURE(o.embedding_dim >= 8 && o.embedding_dim <= 1024, ErrorCode::kInvalidArgument,
             "embedding dimension %d outside 8..1024", o.embedding_dim);
  TLV_ENSURE(o.calibration_frames >= 1 && o.calibration_frames <= 4096, ErrorCode::kInvalidArgument,
             "calibration frames %d outside 1..4096", o.calibration_frames);
  TLV_ENSURE(o.golden_pairs >= 0 && o.golden_pairs <= 8, ErrorCode::kInvalidArgument,
             "golden pairs %d outside 0..8", o.golden_pairs);
  TLV_ENSURE(static_cast<bool>(o.preprocess), ErrorCode::kInvalidArgument,
             "a frame preprocessing function is required");
  return {};
}

Result<std::unique_ptr<Model>> load(const std::vector<std::byte>& file, const char* what) {
  auto m = Model::load(file);
  if (!m.ok()) return m.error().with_context("generated %s model does not load", what);
  return std::move(m).value();
}

void log_ranges(const Model& model, const std::vector<TensorRange>& ranges) {
  const Graph& g = model.graph();
  TLV_LOG(kLogQuantize, kInfo, "activation ranges over the calibration frames (min / max):");
  for (const Operator& op : g.operators) {
    const TensorRange& r = ranges[static_cast<size_t>(op.output)];
    TLV_LOG(kLogQuantize, kInfo, "  %-22.*s %9.3f %9.3f", static_cast<int>(op.name.size()),
            op.name.data(), static_cast<double>(r.min), static_cast<double>(r.max));
  }
}

Status add_golden(ModelBuilder& b, const Model& model,
                  const std::vector<std::vector<float>>& inputs) {
  for (const std::vector<float>& x : inputs) {
    const std::span<const std::byte> in = std::as_bytes(std::span<const float>(x));
    TLV_ASSIGN_OR_RETURN(std::vector<std::byte> out, run_reference(model, in));
    b.metadata().golden.emplace_back(std::vector<std::byte>(in.begin(), in.end()), std::move(out));
  }
  return {};
}

std::string quantization_json(const ReferenceEncoderOptions& o) {
  char text[400];
  std::snprintf(text, sizeof(text),
                "{\"kind\":\"post-training-minmax\",\"calibration\":\"synthetic-touch-frames\","
                "\"frames\":%d,\"seed\":%" PRIu64
                ",\"activations\":\"int8 per-tensor asymmetric\","
                "\"weights\":\"int8 per-channel symmetric [-127,127]\",\"bias\":\"int32\","
                "\"min_range\":%g}",
                o.calibration_frames, o.seed, static_cast<double>(kMinActivationRange));
  return text;
}

}  // namespace

uint64_t reference_encoder_macs(int32_t resolution, int32_t embedding_dim) {
  ReferenceEncoderOptions o;
  o.resolution = resolution;
  o.embedding_dim = embedding_dim;
  return encoder_internal::build_encoder_graph(o).macs;
}

Result<ReferenceEncoder> build_reference_encoder(const ReferenceEncoderOptions& o) {
  TLV_TRY(check_options(o));
  encoder_internal::EncoderGraph g = encoder_internal::build_encoder_graph(o);
  encoder_internal::fill_encoder_metadata(g.builder.metadata(), o);
  ReferenceEncoder result;
  result.macs = g.macs;
  result.layers = g.layers;

  const std::vector<std::byte> fp32_file = g.builder.finish();
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Model> fp32, load(fp32_file, "float"));
  const InputSpec& spec = fp32->metadata().input;
  TLV_ASSIGN_OR_RETURN(auto golden_inputs, make_inputs(o, spec, o.golden_pairs, 1000));

  std::vector<TensorRange> ranges;
  const bool need_ranges = o.dtype == EncoderDType::kInt8 || o.log_activation_ranges;
  if (need_ranges) {
    TLV_ASSIGN_OR_RETURN(auto calibration, make_inputs(o, spec, o.calibration_frames, 2000));
    TLV_ASSIGN_OR_RETURN(ranges, collect_ranges(*fp32, calibration));
    if (o.log_activation_ranges) log_ranges(*fp32, ranges);
  }
  if (o.dtype == EncoderDType::kFloat32) {
    TLV_TRY(add_golden(g.builder, *fp32, golden_inputs));
    result.file = g.builder.finish();
    return result;
  }
  Int8ConversionOptions co;
  co.quantization_json = quantization_json(o);
  TLV_ASSIGN_OR_RETURN(ModelBuilder int8, convert_to_int8(*fp32, ranges, co));
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Model> int8_model, load(int8.finish(), "int8"));
  TLV_TRY(add_golden(int8, *int8_model, golden_inputs));
  result.file = int8.finish();
  return result;
}

}  // namespace tlvlink::quantize
