#pragma once
// Converts a float ONNX model (trained in any framework) into a .tlvm model file.
//
// The converter maps ONNX's NCHW graph onto tlvlink's NHWC one: the model's input becomes
// [1, H, W, C], conv weights are transposed from OIHW to OHWI, BatchNormalization is folded into
// the preceding Conv / Gemm, and ReLU / ReLU6 are fused into the op before them. Operators
// outside the supported set (quantize/README.md, "tlvlink convert") are rejected with an error
// naming the op type, the node and the opset; nothing is approximated silently.
//
//   OnnxImportOptions o;
//   o.source_name = "encoder.onnx";
//   auto r = import_onnx(onnx_bytes, o);   // Result<OnnxImportResult>
//   if (r.ok()) write(r->model);           // loads with Model::load (checked before returning)

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/metadata.h"

namespace tlvlink::quantize {

// Default-domain opsets read. The supported ops kept their semantics over this range; attribute
// forms that moved to inputs (Clip and Pad at 11, Slice at 10, Unsqueeze at 13) are handled.
inline constexpr int64_t kMinOnnxOpset = 7;
inline constexpr int64_t kMaxOnnxOpset = 21;

struct OnnxImportOptions {
  std::string source_name;  // recorded in the provenance (usually the file name)
  std::string model_name;   // metadata name; empty: source_name without its extension
  // Input normalisation recorded in the model: x = (pixel / 255 - mean[c]) / std[c]. One value
  // applies to every channel. Empty: mean 0 and std 1 (the network sees pixel / 255).
  std::vector<float> mean;
  std::vector<float> std;
  // Empty: RGB for 3-channel inputs, Gray for 1-channel inputs.
  std::optional<ChannelOrder> channel_order;
};

struct OnnxImportSummary {
  int64_t opset = 0;          // default-domain opset of the ONNX model
  std::string onnx_producer;  // e.g. "pytorch 1.13.1"
  size_t onnx_nodes = 0;
  size_t operators = 0;               // operators in the written model
  size_t fused = 0;                   // nodes folded or fused away (BN, ReLU, Pad, bias Add ...)
  std::vector<int32_t> input_shape;   // NHWC
  std::vector<int32_t> output_shape;  // graph output 0 as written (4-D outputs are NHWC)
};

struct OnnxImportResult {
  std::vector<std::byte> model;  // the .tlvm file
  OnnxImportSummary summary;
};

// Converts the bytes of an .onnx file. Errors: kFormat (not a readable ONNX model),
// kModelUnsupported (op, opset, attribute, data type or dynamic shape outside what tlvlink
// runs), kModelInvalidTensor (e.g. NaN/Inf in an initializer, named), kModelInvalidOperator
// (inconsistent shapes), kInvalidArgument (bad options).
Result<OnnxImportResult> import_onnx(std::span<const std::byte> onnx_bytes,
                                     const OnnxImportOptions& options);

}  // namespace tlvlink::quantize
