#include "cli/heads.h"

#include <algorithm>
#include <cmath>

namespace tlvlink::cli {
namespace {

HeadPrediction top1(std::string head, const std::vector<std::string_view>& labels,
                    std::vector<float> logits) {
  HeadPrediction p;
  p.head = std::move(head);
  const auto best =
      static_cast<size_t>(std::max_element(logits.begin(), logits.end()) - logits.begin());
  double sum = 0;
  for (float l : logits) sum += std::exp(static_cast<double>(l - logits[best]));
  p.label = std::string(labels[best]);
  p.probability = static_cast<float>(1.0 / sum);
  p.logits = std::move(logits);
  return p;
}

}  // namespace

std::vector<HeadPrediction> predict_heads(const Metadata& m, std::span<const float> e) {
  std::vector<HeadPrediction> out;
  const size_t dim = e.size();
  for (const LinearHead& h : m.linear_heads) {
    std::vector<float> logits(h.labels.size());
    for (size_t k = 0; k < logits.size(); ++k) {
      float acc = h.bias[k];
      for (size_t i = 0; i < dim; ++i) acc += h.weight[k * dim + i] * e[i];
      logits[k] = acc;
    }
    out.push_back(top1(std::string(h.name), h.labels, std::move(logits)));
  }
  double norm = 0;
  for (float v : e) norm += static_cast<double>(v) * static_cast<double>(v);
  const auto inv = static_cast<float>(norm > 0 ? 1.0 / std::sqrt(norm) : 0.0);
  for (const ZeroShotHead& h : m.zero_shot_heads) {
    std::vector<float> logits(h.class_names.size());
    for (size_t k = 0; k < logits.size(); ++k) {
      float acc = 0;
      for (size_t i = 0; i < dim; ++i) acc += h.prompt_matrix[k * dim + i] * e[i] * inv;
      logits[k] = h.logit_scale * acc;
    }
    out.push_back(top1(std::string(h.name), h.class_names, std::move(logits)));
    out.back().kind = "zero-shot";
  }
  return out;
}

}  // namespace tlvlink::cli
