#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "supervised.h is internal to tools/trainer: include its public headers instead"
#endif
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

// The contact regression (with_contact): a linear layer reads two standardised targets from
// the embedding, (ln F - kLogForceMean) / kLogForceScale and (mu - kFrictionMean) /
// kFrictionScale, scored by mean squared error over the rows where the sidecar records them.
// Fixed constants (the simulator's ranges: forces ~1-35 N, friction ~0.2-1.0), so the loss does
// not depend on the batch or the set.
inline constexpr double kLogForceMean = 1.8, kLogForceScale = 0.8;
inline constexpr double kFrictionMean = 0.55, kFrictionScale = 0.2;

class SupervisedHeadsImpl : public torch::nn::Module {
 public:
  SupervisedHeadsImpl(int64_t embedding_dim, bool with_contact);
  // Sum over the three tasks of the mean cross-entropy of the labelled rows (label -1 is
  // ignored; a task without a labelled row in the batch adds 0). embedding [B, D]; labels [B]
  // int64.
  torch::Tensor loss(const torch::Tensor& embedding, const torch::Tensor& material,
                     const torch::Tensor& hard, const torch::Tensor& rough);
  // The contact regression's mean squared error (0 when no row of the batch has a target);
  // log_force / friction [B] float, NaN = no target. Requires with_contact.
  torch::Tensor contact_loss(const torch::Tensor& embedding, const torch::Tensor& log_force,
                             const torch::Tensor& friction);
  // Two views of the same samples should get the same answers: the symmetric KL divergence of
  // each classification head's distributions (mean over the batch, summed over the heads), plus
  // the mean squared difference of the contact read-out when there is one. e1, e2 [B, D].
  torch::Tensor agreement_loss(const torch::Tensor& e1, const torch::Tensor& e2);
  bool has_contact() const { return !contact.is_empty(); }
  torch::nn::Linear material{nullptr}, hard{nullptr}, rough{nullptr};
  torch::nn::Linear contact{nullptr};  // [D] -> (log force, friction), standardised
};
TORCH_MODULE(SupervisedHeads);

// Rows `indices` of a label vector as an int64 tensor.
torch::Tensor label_batch(const std::vector<int32_t>& labels, const std::vector<int64_t>& indices);
// Rows `indices` of a target vector as a float tensor.
torch::Tensor target_batch(const std::vector<float>& targets, const std::vector<int64_t>& indices);

}  // namespace tlvlink::trainer
