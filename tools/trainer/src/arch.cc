// The built-in student architectures and their cost.

#include "tlvlink/trainer/arch.h"

#include <cstdio>

namespace tlvlink::trainer {
namespace {

struct Family {
  const char* name;
  int32_t stages;  // stride-2 stages (5, or 6 for full-resolution input)
  int32_t channels[6];
  int32_t head;
};
// Stages 1-2 stay plain (high resolution is where dense 3x3 costs most); the later stages add
// one residual block each. Widths are multiples of 8 (XNNPACK's int8 kernels work in 8/16
// lanes). `large` is not an edge student: it is the "clearly larger network" of the supervised
// upper bound (issue 16), to show what capacity costs. The `-hr` families take the GelSight
// frame at full resolution (240x320: no resize, so a texture finer than the 96x128 grid's
// 0.16 mm pixels still reaches the network) through a sixth, narrow stride-2 stage.
constexpr Family kFamilies[] = {
    {"large", 5, {32, 64, 128, 256, 512, 0}, 1024},   {"small", 5, {16, 32, 64, 128, 256, 0}, 512},
    {"tiny", 5, {16, 24, 32, 64, 128, 0}, 256},       {"tiny-hr", 6, {8, 16, 24, 32, 64, 128}, 256},
    {"large-hr", 6, {16, 32, 64, 96, 192, 384}, 768},
};
constexpr int32_t kFirstResidualStage = 2;  // 0-based

}  // namespace

std::string arch_names() {
  std::string s;
  for (const Family& f : kFamilies) s += (s.empty() ? "" : ", ") + std::string(f.name);
  return s;
}

int32_t conv_output_size(int32_t in, int32_t kernel, int32_t stride) {
  return (in + 2 * (kernel / 2) - kernel) / stride + 1;
}

Result<ArchSpec> make_arch(std::string_view name, int32_t input_height, int32_t input_width,
                           int32_t embedding_dim) {
  TLV_ENSURE(input_height >= kMinInputSide && input_height <= kMaxInputSide &&
                 input_width >= kMinInputSide && input_width <= kMaxInputSide,
             ErrorCode::kInvalidArgument, "input size %dx%d: each side must be in %d..%d",
             input_height, input_width, kMinInputSide, kMaxInputSide);
  TLV_ENSURE(embedding_dim >= kMinEmbeddingDim && embedding_dim <= kMaxEmbeddingDim,
             ErrorCode::kInvalidArgument, "embedding dimension %d outside %d..%d", embedding_dim,
             kMinEmbeddingDim, kMaxEmbeddingDim);
  for (const Family& f : kFamilies) {
    if (name != f.name) continue;
    ArchSpec spec;
    spec.name = f.name;
    spec.input_height = input_height;
    spec.input_width = input_width;
    spec.embedding_dim = embedding_dim;
    for (int32_t stage = 0; stage < f.stages; ++stage) {
      spec.layers.push_back({LayerKind::kConvBnRelu6, f.channels[stage], 3, 2});
      if (stage >= kFirstResidualStage) {
        spec.layers.push_back({LayerKind::kResidualBnRelu6, f.channels[stage], 3, 1});
      }
    }
    spec.layers.push_back({LayerKind::kConvBnRelu6, f.head, 1, 1});
    return spec;
  }
  return Error::make(ErrorCode::kInvalidArgument, "unknown architecture '%.*s' (known: %s)",
                     static_cast<int>(name.size()), name.data(), arch_names().c_str());
}

ArchStats arch_stats(const ArchSpec& spec) {
  ArchStats s;
  int32_t h = spec.input_height, w = spec.input_width, c = 3;
  for (const LayerSpec& l : spec.layers) {
    h = conv_output_size(h, l.kernel, l.stride);
    w = conv_output_size(w, l.kernel, l.stride);
    const auto weights =
        static_cast<uint64_t>(l.out_channels) * static_cast<uint64_t>(l.kernel * l.kernel * c);
    s.macs += weights * static_cast<uint64_t>(h) * static_cast<uint64_t>(w);
    s.params += weights + 2 * static_cast<uint64_t>(l.out_channels);       // + BN gamma, beta
    s.deployed_params += weights + static_cast<uint64_t>(l.out_channels);  // + folded bias
    c = l.out_channels;
  }
  const auto fc = static_cast<uint64_t>(c) * static_cast<uint64_t>(spec.embedding_dim);
  s.macs += fc;
  s.params += fc + static_cast<uint64_t>(spec.embedding_dim);
  s.deployed_params += fc + static_cast<uint64_t>(spec.embedding_dim);
  s.final_height = h;
  s.final_width = w;
  s.final_channels = c;
  return s;
}

std::string describe_arch(const ArchSpec& spec) {
  const ArchStats s = arch_stats(spec);
  char text[160];
  std::snprintf(text, sizeof(text),
                "%s %dx%d -> %d: %.1f MMAC, %.2f M parameters (%.2f M deployed)", spec.name.c_str(),
                spec.input_height, spec.input_width, spec.embedding_dim,
                static_cast<double>(s.macs) / 1e6, static_cast<double>(s.params) / 1e6,
                static_cast<double>(s.deployed_params) / 1e6);
  return text;
}

}  // namespace tlvlink::trainer
