#pragma once
// BatchNorm folding for export: conv(x; W, b) followed by BN (eval: running mean/var) equals
// conv(x; W', b') with, per output channel c,
//   s = gamma[c] / sqrt(var[c] + eps),  W'[c] = s W[c],  b'[c] = s (b[c] - mean[c]) + beta[c].
// quantization.md: fold before choosing int8 weight scales. Computed in double, stored float.

#include <cstdint>
#include <span>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::trainer {

struct BatchNormParams {
  std::vector<float> gamma, beta, running_mean, running_var;
  float eps = 1e-5f;
};

struct ConvShape {
  int32_t out_channels = 0, in_channels = 0, kernel_h = 1, kernel_w = 1;
  size_t weights() const {
    return static_cast<size_t>(out_channels) * static_cast<size_t>(in_channels) *
           static_cast<size_t>(kernel_h) * static_cast<size_t>(kernel_w);
  }
};

struct FoldedConv {
  std::vector<float> weight_ohwi;  // [out, kh, kw, in]: the runtime's Conv2D layout (NHWC)
  std::vector<float> bias;         // [out]
};

// `weight_oihw` is libtorch's [out, in, kh, kw]; `conv_bias` may be empty (no bias). Errors
// (kInvalidArgument): sizes that do not match `shape`, a negative variance, or a non-finite
// result (e.g. var + eps == 0), naming the channel.
Result<FoldedConv> fold_batchnorm(std::span<const float> weight_oihw, const ConvShape& shape,
                                  std::span<const float> conv_bias, const BatchNormParams& bn);

// OIHW -> OHWI without folding (a conv with no BN).
std::vector<float> oihw_to_ohwi(std::span<const float> weight_oihw, const ConvShape& shape);

}  // namespace tlvlink::trainer
