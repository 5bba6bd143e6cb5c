#include "tlvlink/heads/head_math.h"

#include <algorithm>
#include <cmath>

namespace tlvlink::heads {

void linear_logits(std::span<const float> weight, std::span<const float> bias,
                   std::span<const float> x, std::span<float> logits) {
  const size_t dim = x.size();
  for (size_t k = 0; k < logits.size(); ++k) {
    float acc = bias[k];
    for (size_t i = 0; i < dim; ++i) acc += weight[k * dim + i] * x[i];
    logits[k] = acc;
  }
}

void zero_shot_logits(std::span<const float> prompt_matrix, float logit_scale,
                      std::span<const float> e, std::span<float> logits) {
  const size_t dim = e.size();
  double norm = 0;
  for (float v : e) norm += static_cast<double>(v) * static_cast<double>(v);
  const auto inv = static_cast<float>(norm > 0 ? 1.0 / std::sqrt(norm) : 0.0);
  for (size_t k = 0; k < logits.size(); ++k) {
    float acc = 0;
    for (size_t i = 0; i < dim; ++i) acc += prompt_matrix[k * dim + i] * e[i] * inv;
    logits[k] = logit_scale * acc;
  }
}

float grasp_logit(std::span<const float> weight, float bias,
                  std::span<const std::span<const float>> features) {
  float acc = bias;
  size_t w = 0;
  for (const std::span<const float> f : features) {
    for (size_t i = 0; i < f.size(); ++i) acc += weight[w + i] * f[i];
    w += f.size();
  }
  return acc;
}

int32_t argmax(std::span<const float> v) {
  return static_cast<int32_t>(std::max_element(v.begin(), v.end()) - v.begin());
}

int32_t softmax(std::span<const float> logits, std::span<float> probabilities) {
  const int32_t top = argmax(logits);
  const float max = logits[static_cast<size_t>(top)];
  double sum = 0;
  for (float l : logits) sum += std::exp(static_cast<double>(l - max));
  for (size_t k = 0; k < logits.size(); ++k) {
    probabilities[k] = static_cast<float>(std::exp(static_cast<double>(logits[k] - max)) / sum);
  }
  probabilities[static_cast<size_t>(top)] = static_cast<float>(1.0 / sum);
  return top;
}

float sigmoid(float logit) { return 1.0f / (1.0f + std::exp(-logit)); }

}  // namespace tlvlink::heads
