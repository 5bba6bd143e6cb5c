#pragma once
// The edge student architectures: plain CNNs built only from operators the int8 runtime runs
// fast on XNNPACK (int8 depthwise is XNNPACK's slow kernel on x86; dense 3x3 and 1x1
// convolutions are fast). No depthwise, no grouped convolutions.
//
//   input [1,H,W,3] float (default 96x128, the 240x320 GelSight frame's aspect)
//   -> stride-2 3x3 conv + BN + ReLU6, five times (channels c1..c5; H/32 x W/32 at the end),
//      stages 3..5 followed by one residual block: ReLU6(x + BN(conv3x3(x)))
//   -> 1x1 conv to the head width + BN + ReLU6 -> GlobalAveragePool -> FC to the embedding.
// BatchNorm is folded into the convolutions at export, ReLU6 fused into Conv2D / Add.
//
//   small: c = 16, 32, 64, 128, 256, head 512  (~38 MMAC, ~1.4 M parameters at 96x128)
//   tiny:  c = 16, 24, 32, 64, 128,  head 256  (~13 MMAC, ~0.4 M parameters at 96x128)
//   large: c = 32, 64, 128, 256, 512, head 1024 (~150 MMAC, ~5.5 M parameters at 96x128): not an
//          edge student, the larger network of the supervised upper bound
// Exact figures for any input size: arch_macs() / arch_params(); `tlvlink train --help-arch`.
// Host-side description only (no libtorch here): the trainer builds the libtorch module from it
// and the exporter the .tlvm graph, so both walk the same list.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::trainer {

inline constexpr int32_t kMinInputSide = 32;
inline constexpr int32_t kMaxInputSide = 512;
inline constexpr int32_t kMinEmbeddingDim = 8;
inline constexpr int32_t kMaxEmbeddingDim = 4096;
inline constexpr float kBatchNormEps = 1e-5f;  // libtorch's default, used by every BN layer

enum class LayerKind : uint8_t {
  kConvBnRelu6,      // 3x3 or 1x1 conv (no bias) + BatchNorm + ReLU6
  kResidualBnRelu6,  // ReLU6(x + BN(conv 3x3 stride 1 (x))), channels unchanged
};

struct LayerSpec {
  LayerKind kind = LayerKind::kConvBnRelu6;
  int32_t out_channels = 0;
  int32_t kernel = 3;  // 3 (padding 1) or 1 (padding 0)
  int32_t stride = 1;  // 1 or 2
};

struct ArchSpec {
  std::string name;  // "large", "small", "tiny"
  int32_t input_height = 96, input_width = 128;
  std::vector<LayerSpec> layers;  // in order; the last one is the 1x1 head conv
  int32_t embedding_dim = 128;    // FC output = the text encoder's dimension
};

// Names of the built-in architectures, for --help and error messages: "large, small, tiny".
std::string arch_names();
// The named architecture at an input size and embedding dimension. Errors (kInvalidArgument):
// unknown name, sides outside kMinInputSide..kMaxInputSide, dim outside the embedding range.
Result<ArchSpec> make_arch(std::string_view name, int32_t input_height, int32_t input_width,
                           int32_t embedding_dim);

// Spatial size after each stride: out = (in + 2*pad - k) / stride + 1 with pad = k / 2.
int32_t conv_output_size(int32_t in, int32_t kernel, int32_t stride);

struct ArchStats {
  uint64_t macs = 0;    // multiply-accumulates per frame (convs + FC; BN folded, so free)
  uint64_t params = 0;  // trainable parameters (conv weights, BN scale/shift, FC weight/bias)
  uint64_t deployed_params = 0;  // after folding: conv weights + biases, FC weight + bias
  int32_t final_height = 0, final_width = 0, final_channels = 0;
};
ArchStats arch_stats(const ArchSpec& spec);
// "small 96x128 -> 128: 38.4 MMAC, 1.37 M parameters (1.37 M deployed)"
std::string describe_arch(const ArchSpec& spec);

}  // namespace tlvlink::trainer
