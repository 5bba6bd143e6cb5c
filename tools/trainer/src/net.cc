// EncoderNet, batches and the contrastive loss.

#include "net.h"

#include <torch/nn/functional/loss.h>
#include <torch/nn/init.h>
#include <torch/utils.h>

#include <algorithm>
#include <cstring>

namespace tlvlink::trainer {

EncoderNetImpl::EncoderNetImpl(ArchSpec spec) : spec_(std::move(spec)) {
  int64_t in = 3;
  for (size_t i = 0; i < spec_.layers.size(); ++i) {
    const LayerSpec& l = spec_.layers[i];
    auto conv = torch::nn::Conv2d(torch::nn::Conv2dOptions(in, l.out_channels, l.kernel)
                                      .stride(l.stride)
                                      .padding(l.kernel / 2)
                                      .bias(false));
    auto bn = torch::nn::BatchNorm2d(
        torch::nn::BatchNorm2dOptions(l.out_channels).eps(static_cast<double>(kBatchNormEps)));
    torch::nn::init::kaiming_normal_(conv->weight, 0.0, torch::kFanOut, torch::kReLU);
    if (l.kind == LayerKind::kResidualBnRelu6) {
      // Zero-initialised residual BN: every block starts as the identity (Goyal et al. 2017).
      torch::nn::init::zeros_(bn->weight);
    }
    convs.push_back(register_module("conv" + std::to_string(i), conv));
    norms.push_back(register_module("bn" + std::to_string(i), bn));
    in = l.out_channels;
  }
  fc = register_module("fc", torch::nn::Linear(in, spec_.embedding_dim));
}

torch::Tensor EncoderNetImpl::forward(torch::Tensor x) {
  for (size_t i = 0; i < convs.size(); ++i) {
    torch::Tensor y = norms[i]->forward(convs[i]->forward(x));
    if (spec_.layers[i].kind == LayerKind::kResidualBnRelu6) y = y + x;
    x = torch::clamp(y, 0.0, 6.0);  // ReLU6
  }
  return fc->forward(x.mean({2, 3}));
}

torch::Tensor image_batch(const std::vector<uint8_t>& pixels, int32_t height, int32_t width,
                          const std::vector<int64_t>& indices, const std::vector<float>& mean,
                          const std::vector<float>& std) {
  const size_t stride = static_cast<size_t>(height) * static_cast<size_t>(width) * 3;
  const auto b = static_cast<int64_t>(indices.size());
  torch::Tensor raw = torch::empty({b, height, width, 3}, torch::kUInt8);
  auto* dst = raw.data_ptr<uint8_t>();
  for (size_t i = 0; i < indices.size(); ++i) {
    std::memcpy(dst + i * stride, pixels.data() + static_cast<size_t>(indices[i]) * stride, stride);
  }
  const torch::Tensor m = torch::tensor(mean).view({1, 1, 1, 3});
  const torch::Tensor s = torch::tensor(std).view({1, 1, 1, 3});
  // Same float32 operations, same order as tools::preprocess: (v / 255 - mean) / std.
  return ((raw.to(torch::kFloat32) / 255.0f - m) / s).permute({0, 3, 1, 2}).contiguous();
}

torch::Tensor clip_loss(const torch::Tensor& x, const torch::Tensor& y,
                        const torch::Tensor& scale) {
  namespace F = torch::nn::functional;
  const torch::Tensor xn = F::normalize(x, F::NormalizeFuncOptions().dim(1));
  const torch::Tensor yn = F::normalize(y, F::NormalizeFuncOptions().dim(1));
  const torch::Tensor logits = scale * torch::matmul(xn, yn.t());
  const torch::Tensor target = torch::arange(x.size(0), torch::kLong);
  return 0.5 * (F::cross_entropy(logits, target) + F::cross_entropy(logits.t(), target));
}

torch::Tensor embed_all(EncoderNet& net, const std::vector<uint8_t>& pixels, int32_t height,
                        int32_t width, int64_t n, const std::vector<float>& mean,
                        const std::vector<float>& std) {
  constexpr int64_t kChunk = 256;
  const bool was_training = net->is_training();
  net->eval();
  torch::NoGradGuard no_grad;
  std::vector<torch::Tensor> parts;
  for (int64_t start = 0; start < n; start += kChunk) {
    std::vector<int64_t> idx;
    for (int64_t i = start; i < std::min(n, start + kChunk); ++i) idx.push_back(i);
    parts.push_back(net->forward(image_batch(pixels, height, width, idx, mean, std)));
  }
  net->train(was_training);
  return torch::cat(parts, 0);
}

bool decays(const std::string& name, const torch::Tensor& p) {
  return p.dim() >= 2 && name.find("bn") == std::string::npos;
}

std::string first_line(const char* what) {
  std::string s(what);
  const size_t nl = s.find('\n');
  return nl == std::string::npos ? s : s.substr(0, nl);
}

}  // namespace tlvlink::trainer
