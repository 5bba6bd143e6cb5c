// tlvlink convert MODEL.onnx -o MODEL.tlvm: imports a float ONNX model (any framework's export)
// into a .tlvm file, NCHW -> NHWC, BatchNorm folded, activations fused.

#include <filesystem>

#include "common.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/format.h"
#include "tlvlink/quantize/onnx_import.h"

namespace tlvlink::cli {
namespace {

// Largest .onnx file read (protobuf's own limit is 2 GB; edge models are a few MB).
constexpr size_t kMaxOnnxBytes = size_t{1} << 30;

struct ConvertOptions {
  std::string input;
  std::string output;
  std::string name;
  std::vector<float> mean;
  std::vector<float> std;
  std::string channel_order;  // empty: from the channel count
};

std::optional<ChannelOrder> parse_order(const std::string& s) {
  if (s == "rgb") return ChannelOrder::kRGB;
  if (s == "bgr") return ChannelOrder::kBGR;
  if (s == "gray") return ChannelOrder::kGray;
  return std::nullopt;
}

int run_convert(const ConvertOptions& o) {
  auto bytes = tools::read_file(o.input, kMaxOnnxBytes);
  if (!bytes.ok()) return report_error("convert", bytes.error());
  quantize::OnnxImportOptions options;
  options.source_name = std::filesystem::path(o.input).filename().string();
  options.model_name = o.name;
  options.mean = o.mean;
  options.std = o.std;
  options.channel_order = parse_order(o.channel_order);
  auto result = quantize::import_onnx(*bytes, options);
  if (!result.ok())
    return report_error("convert", result.error().with_context("%s", o.input.c_str()));
  if (Status s = tools::write_file(o.output, result->model); !s.ok()) {
    return report_error("convert", s.error());
  }
  const quantize::OnnxImportSummary& s = result->summary;
  auto shape = [](const std::vector<int32_t>& dims) {
    Shape sh;
    for (int32_t d : dims) sh.dims[sh.rank++] = d;
    return tools::shape_string(sh);
  };
  std::printf("converted %s (%s, opset %lld, %zu nodes) -> %s\n", o.input.c_str(),
              s.onnx_producer.c_str(), static_cast<long long>(s.opset), s.onnx_nodes,
              o.output.c_str());
  std::printf("  %zu operators (%zu nodes folded or fused), input %s NHWC, output %s, %s\n",
              s.operators, s.fused, shape(s.input_shape).c_str(), shape(s.output_shape).c_str(),
              tools::human_bytes(result->model.size()).c_str());
  return kExitOk;
}

}  // namespace

void add_convert_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ConvertOptions>();
  CLI::App* cmd = app.add_subcommand(
      "convert",
      "Convert a float ONNX model (Conv, Gemm/MatMul, BatchNorm, ReLU/Clip, Add, Mul, pools, "
      "Flatten/Reshape, Sigmoid, Pad) into a .tlvm model; NCHW becomes NHWC, the input "
      "[1,H,W,C]. Unsupported ops are reported with their node name.");
  cmd->add_option("model", o->input, "ONNX model file")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", o->output, "Output .tlvm file")->required();
  cmd->add_option("--name", o->name, "Model name in the metadata (default: the file's stem)");
  cmd->add_option("--mean", o->mean,
                  "Per-channel mean applied to pixel/255, comma-separated or one value for all "
                  "(default 0)")
      ->delimiter(',');
  cmd->add_option("--std", o->std,
                  "Per-channel std applied after the mean, e.g. 0.229,0.224,0.225 (default 1)")
      ->delimiter(',');
  cmd->add_option("--channel-order", o->channel_order,
                  "Channel order of the input: rgb, bgr or gray (default: rgb for 3 channels, "
                  "gray for 1)")
      ->check(CLI::IsMember({"rgb", "bgr", "gray"}));
  cmd->footer(kExitCodeFooter);
  cmd->callback([o, &exit_code] { exit_code = run_convert(*o); });
}

}  // namespace tlvlink::cli
