#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "net.h is internal to tools/trainer: include its public headers instead"
#endif
// libtorch side of the trainer (internal; includes torch headers — keep out of non-torch code).
// EncoderNet is the module an ArchSpec describes; the exporter walks the same layer list.

#include <torch/nn/module.h>
#include <torch/nn/modules/batchnorm.h>
#include <torch/nn/modules/container/modulelist.h>
#include <torch/nn/modules/conv.h>
#include <torch/nn/modules/linear.h>
#include <torch/nn/pimpl.h>

// After the modules: libtorch 1.13's functional headers are not self-contained (c10 types).
#include <torch/nn/functional/normalization.h>

#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/trainer/arch.h"

namespace tlvlink::trainer {

class EncoderNetImpl : public torch::nn::Module {
 public:
  explicit EncoderNetImpl(ArchSpec spec);
  // x: normalised NCHW float [N, 3, H, W] -> embedding [N, D] (not normalised).
  torch::Tensor forward(torch::Tensor x);
  const ArchSpec& spec() const { return spec_; }
  // One conv + BN per ArchSpec layer, in order, then the FC.
  std::vector<torch::nn::Conv2d> convs;
  std::vector<torch::nn::BatchNorm2d> norms;
  torch::nn::Linear fc{nullptr};

 private:
  ArchSpec spec_;
};
TORCH_MODULE(EncoderNet);

// Gathers rows `indices` of a uint8 image block [n, h, w, 3] into a normalised float NCHW batch:
// (pixel / 255 - mean[c]) / std[c], exactly the arithmetic of tools::preprocess.
torch::Tensor image_batch(const std::vector<uint8_t>& pixels, int32_t height, int32_t width,
                          const std::vector<int64_t>& indices, const std::vector<float>& mean,
                          const std::vector<float>& std);

// The CLIP/TLV-Link loss: x, y [B, D] (L2-normalised here), logits = scale * x y^T, symmetric
// cross-entropy with the diagonal as targets.
torch::Tensor clip_loss(const torch::Tensor& x, const torch::Tensor& y, const torch::Tensor& scale);

// Runs `net` in eval mode over all `n` images in chunks; returns [n, D] float (no grad).
torch::Tensor embed_all(EncoderNet& net, const std::vector<uint8_t>& pixels, int32_t height,
                        int32_t width, int64_t n, const std::vector<float>& mean,
                        const std::vector<float>& std);

// Whether a parameter gets weight decay: conv and FC weights yes; BN, biases, scales no (CLIP).
bool decays(const std::string& parameter_name, const torch::Tensor& parameter);

// libtorch reports failures as c10::Error with a long backtrace; error messages keep its first
// line.
std::string first_line(const char* what);

}  // namespace tlvlink::trainer
