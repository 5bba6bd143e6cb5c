// Supervised heads: cross-entropy on the simulator's labels.

#include "supervised.h"

#include <torch/nn/functional/loss.h>

namespace tlvlink::trainer {
namespace {

// Mean cross-entropy over the rows whose label is not -1; 0 when there is none (cross_entropy
// with every target ignored would divide 0 by 0).
torch::Tensor masked_ce(const torch::Tensor& logits, const torch::Tensor& labels) {
  namespace F = torch::nn::functional;
  if (labels.ge(0).sum().item<int64_t>() == 0) return torch::zeros({}, logits.options());
  return F::cross_entropy(logits, labels, F::CrossEntropyFuncOptions().ignore_index(-1));
}

}  // namespace

SupervisedHeadsImpl::SupervisedHeadsImpl(int64_t dim) {
  material = register_module("material", torch::nn::Linear(dim, kMaterialClasses));
  hard = register_module("hard", torch::nn::Linear(dim, 2));
  rough = register_module("rough", torch::nn::Linear(dim, 2));
}

torch::Tensor SupervisedHeadsImpl::loss(const torch::Tensor& e, const torch::Tensor& m,
                                        const torch::Tensor& h, const torch::Tensor& r) {
  return masked_ce(material->forward(e), m) + masked_ce(hard->forward(e), h) +
         masked_ce(rough->forward(e), r);
}

torch::Tensor label_batch(const std::vector<int32_t>& labels, const std::vector<int64_t>& idx) {
  torch::Tensor t = torch::empty({static_cast<int64_t>(idx.size())}, torch::kLong);
  auto* p = t.data_ptr<int64_t>();
  for (size_t i = 0; i < idx.size(); ++i) p[i] = labels[static_cast<size_t>(idx[i])];
  return t;
}

}  // namespace tlvlink::trainer
