// BatchNorm folding and the OIHW -> OHWI weight layout change.

#include "tlvlink/trainer/fold.h"

#include <cmath>

namespace tlvlink::trainer {

std::vector<float> oihw_to_ohwi(std::span<const float> w, const ConvShape& s) {
  std::vector<float> out(s.weights());
  const auto ci = static_cast<size_t>(s.in_channels), kh = static_cast<size_t>(s.kernel_h),
             kw = static_cast<size_t>(s.kernel_w);
  for (size_t o = 0; o < static_cast<size_t>(s.out_channels); ++o)
    for (size_t i = 0; i < ci; ++i)
      for (size_t y = 0; y < kh; ++y)
        for (size_t x = 0; x < kw; ++x)
          out[((o * kh + y) * kw + x) * ci + i] = w[((o * ci + i) * kh + y) * kw + x];
  return out;
}

Result<FoldedConv> fold_batchnorm(std::span<const float> weight_oihw, const ConvShape& shape,
                                  std::span<const float> conv_bias, const BatchNormParams& bn) {
  const auto cout = static_cast<size_t>(shape.out_channels);
  TLV_ENSURE(shape.out_channels > 0 && weight_oihw.size() == shape.weights(),
             ErrorCode::kInvalidArgument, "conv weights hold %zu values, shape needs %zu",
             weight_oihw.size(), shape.weights());
  TLV_ENSURE(conv_bias.empty() || conv_bias.size() == cout, ErrorCode::kInvalidArgument,
             "conv bias holds %zu values for %zu output channels", conv_bias.size(), cout);
  TLV_ENSURE(bn.gamma.size() == cout && bn.beta.size() == cout && bn.running_mean.size() == cout &&
                 bn.running_var.size() == cout,
             ErrorCode::kInvalidArgument,
             "BatchNorm parameters sized %zu/%zu/%zu/%zu for %zu channels", bn.gamma.size(),
             bn.beta.size(), bn.running_mean.size(), bn.running_var.size(), cout);
  FoldedConv f;
  f.weight_ohwi = oihw_to_ohwi(weight_oihw, shape);
  f.bias.resize(cout);
  const size_t per_channel = shape.weights() / cout;
  for (size_t c = 0; c < cout; ++c) {
    TLV_ENSURE(bn.running_var[c] >= 0, ErrorCode::kInvalidArgument,
               "BatchNorm channel %zu has negative running variance %g", c,
               static_cast<double>(bn.running_var[c]));
    const double s =
        static_cast<double>(bn.gamma[c]) /
        std::sqrt(static_cast<double>(bn.running_var[c]) + static_cast<double>(bn.eps));
    const double b = conv_bias.empty() ? 0.0 : static_cast<double>(conv_bias[c]);
    const double folded_bias =
        s * (b - static_cast<double>(bn.running_mean[c])) + static_cast<double>(bn.beta[c]);
    TLV_ENSURE(std::isfinite(s) && std::isfinite(folded_bias), ErrorCode::kInvalidArgument,
               "BatchNorm channel %zu folds to a non-finite scale/bias (var %g, eps %g)", c,
               static_cast<double>(bn.running_var[c]), static_cast<double>(bn.eps));
    for (size_t k = 0; k < per_channel; ++k) {
      float& w = f.weight_ohwi[c * per_channel + k];  // OHWI keeps a channel's weights together
      w = static_cast<float>(s * static_cast<double>(w));
    }
    f.bias[c] = static_cast<float>(folded_bias);
  }
  return f;
}

}  // namespace tlvlink::trainer
