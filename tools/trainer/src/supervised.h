#pragma once
// Supervised heads of the trainer (internal; libtorch): linear layers on the student's raw
// embedding for the labels a simulated set records (material: 20 Touch-and-Go classes,
// hard/soft, rough/smooth), trained with cross-entropy. They serve two objectives beside
// TLV-Link's InfoNCE (trainer.h Objective): "supervised" (the supervised upper bound: the same
// student trained on the labels alone) and "tlv-link+supervised" (both losses, summed). The
// heads are training scaffolding: export writes only the encoder; `tlvlink heads fit` fits the
// model's heads on runtime embeddings as for any other model.

#include <torch/nn/module.h>
#include <torch/nn/modules/linear.h>
#include <torch/nn/pimpl.h>

#include <cstdint>
#include <vector>

namespace tlvlink::trainer {

inline constexpr int64_t kMaterialClasses = 20;

class SupervisedHeadsImpl : public torch::nn::Module {
 public:
  explicit SupervisedHeadsImpl(int64_t embedding_dim);
  // Sum over the three tasks of the mean cross-entropy of the labelled rows (label -1 is
  // ignored; a task without a labelled row in the batch adds 0). embedding [B, D]; labels [B]
  // int64.
  torch::Tensor loss(const torch::Tensor& embedding, const torch::Tensor& material,
                     const torch::Tensor& hard, const torch::Tensor& rough);
  torch::nn::Linear material{nullptr}, hard{nullptr}, rough{nullptr};
};
TORCH_MODULE(SupervisedHeads);

// Rows `indices` of a label vector as an int64 tensor.
torch::Tensor label_batch(const std::vector<int32_t>& labels, const std::vector<int64_t>& indices);

}  // namespace tlvlink::trainer
