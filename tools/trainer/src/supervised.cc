// Supervised heads: cross-entropy on the simulator's labels.

#include "supervised.h"

#include <torch/nn/functional/activation.h>
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

SupervisedHeadsImpl::SupervisedHeadsImpl(int64_t dim, bool with_contact) {
  material = register_module("material", torch::nn::Linear(dim, kMaterialClasses));
  hard = register_module("hard", torch::nn::Linear(dim, 2));
  rough = register_module("rough", torch::nn::Linear(dim, 2));
  if (with_contact) contact = register_module("contact", torch::nn::Linear(dim, 2));
}

torch::Tensor SupervisedHeadsImpl::contact_loss(const torch::Tensor& e,
                                                const torch::Tensor& log_force,
                                                const torch::Tensor& friction) {
  const torch::Tensor target = torch::stack(
      {(log_force - kLogForceMean) / kLogForceScale, (friction - kFrictionMean) / kFrictionScale},
      1);
  const torch::Tensor known = torch::isfinite(target);
  const int64_t n = known.sum().item<int64_t>();
  if (n == 0) return torch::zeros({}, e.options());
  const torch::Tensor diff = torch::where(known, contact->forward(e) - torch::nan_to_num(target),
                                          torch::zeros({}, e.options()));
  return diff.pow(2).sum() / static_cast<double>(n);
}

torch::Tensor SupervisedHeadsImpl::loss(const torch::Tensor& e, const torch::Tensor& m,
                                        const torch::Tensor& h, const torch::Tensor& r) {
  return masked_ce(material->forward(e), m) + masked_ce(hard->forward(e), h) +
         masked_ce(rough->forward(e), r);
}

torch::Tensor SupervisedHeadsImpl::agreement_loss(const torch::Tensor& e1,
                                                  const torch::Tensor& e2) {
  namespace F = torch::nn::functional;
  const auto symmetric_kl = [](const torch::Tensor& a, const torch::Tensor& b) {
    const torch::Tensor la = F::log_softmax(a, F::LogSoftmaxFuncOptions(1));
    const torch::Tensor lb = F::log_softmax(b, F::LogSoftmaxFuncOptions(1));
    return ((la.exp() - lb.exp()) * (la - lb)).sum(1).mean();  // KL(a||b) + KL(b||a)
  };
  torch::Tensor loss = symmetric_kl(material->forward(e1), material->forward(e2)) +
                       symmetric_kl(hard->forward(e1), hard->forward(e2)) +
                       symmetric_kl(rough->forward(e1), rough->forward(e2));
  if (has_contact()) loss = loss + (contact->forward(e1) - contact->forward(e2)).pow(2).mean();
  return loss;
}

torch::Tensor label_batch(const std::vector<int32_t>& labels, const std::vector<int64_t>& idx) {
  torch::Tensor t = torch::empty({static_cast<int64_t>(idx.size())}, torch::kLong);
  auto* p = t.data_ptr<int64_t>();
  for (size_t i = 0; i < idx.size(); ++i) p[i] = labels[static_cast<size_t>(idx[i])];
  return t;
}

torch::Tensor target_batch(const std::vector<float>& targets, const std::vector<int64_t>& idx) {
  torch::Tensor t = torch::empty({static_cast<int64_t>(idx.size())}, torch::kFloat);
  auto* p = t.data_ptr<float>();
  for (size_t i = 0; i < idx.size(); ++i) p[i] = targets[static_cast<size_t>(idx[i])];
  return t;
}

}  // namespace tlvlink::trainer
