#include "cli/common.h"

#include <cstdio>

#include "tlvlink/quant_math.h"

namespace tlvlink::cli {

int report_error(const char* command, const Error& error) {
  std::fprintf(stderr, "tlvlink %s: error [%s]: %s\n", command, error_code_name(error.code()),
               error.message());
  return error.code() == ErrorCode::kInvalidArgument ? kExitUsage : kExitFailure;
}

Result<std::unique_ptr<Model>> load_model(const std::string& path) {
  auto model = Model::load_file(path.c_str());
  if (!model.ok()) return model.error().with_context("%s", path.c_str());
  return std::move(model).value();
}

void ExecutorFlags::add_to(CLI::App& app) {
  app.add_option("--executor,-e", executor, "Executor: xnnpack (default) or reference")
      ->check(CLI::IsMember({"xnnpack", "reference"}))
      ->capture_default_str();
  app.add_option("--threads,-t", threads,
                 "Threads for the XNNPACK thread pool (reference ignores it)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
}

ExecutorOptions ExecutorFlags::options() const {
  ExecutorOptions o;
  o.threads = threads;
  return o;
}

Result<std::unique_ptr<Executor>> create_executor(const Model& model, const ExecutorFlags& flags) {
  TLV_ASSIGN_OR_RETURN(ExecutorKind kind, parse_executor_kind(flags.executor));
  auto exec = make_executor(model, kind, flags.options());
  if (!exec.ok())
    return exec.error().with_context("creating the %s executor", flags.executor.c_str());
  return std::move(exec).value();
}

std::string shape_string(const Shape& shape) {
  std::string s = "[";
  for (size_t i = 0; i < shape.rank; ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + "]";
}

std::string human_bytes(size_t bytes) {
  char text[32];
  if (bytes >= 1000 * 1000) {
    std::snprintf(text, sizeof(text), "%.2f MB", static_cast<double>(bytes) / 1e6);
  } else if (bytes >= 1000) {
    std::snprintf(text, sizeof(text), "%.1f kB", static_cast<double>(bytes) / 1e3);
  } else {
    std::snprintf(text, sizeof(text), "%zu B", bytes);
  }
  return text;
}

std::vector<float> output_as_floats(const Tensor& t, std::span<const std::byte> bytes) {
  std::vector<float> out;
  const size_t n = t.shape.elements();
  out.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    switch (t.dtype) {
      case DType::kFloat32: out.push_back(reinterpret_cast<const float*>(bytes.data())[i]); break;
      case DType::kInt8: {
        const int8_t q = reinterpret_cast<const int8_t*>(bytes.data())[i];
        out.push_back(t.quant.quantized()
                          ? dequantize_value(q, t.quant.scale[0], t.quant.zero_point[0])
                          : static_cast<float>(q));
        break;
      }
      case DType::kInt32:
        out.push_back(static_cast<float>(reinterpret_cast<const int32_t*>(bytes.data())[i]));
        break;
      case DType::kUInt8:
        out.push_back(static_cast<float>(reinterpret_cast<const uint8_t*>(bytes.data())[i]));
        break;
    }
  }
  return out;
}

}  // namespace tlvlink::cli
