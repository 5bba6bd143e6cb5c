#include "tlvlink/pipeline/smoother.h"

#include <algorithm>
#include <cmath>

namespace tlvlink::pipeline {

ProbabilitySmoother::ProbabilitySmoother(int32_t labels, int64_t tau_ns)
    : state_(static_cast<size_t>(labels), 0.0f), tau_ns_(tau_ns) {}

void ProbabilitySmoother::add(std::span<const float> p, int64_t t_ns, std::span<float> out) {
  if (!started_ || tau_ns_ <= 0) {
    std::copy(p.begin(), p.end(), state_.begin());
    started_ = true;
  } else {
    const double dt = static_cast<double>(std::max<int64_t>(t_ns - last_ns_, 0));
    const auto w = static_cast<float>(1.0 - std::exp(-dt / static_cast<double>(tau_ns_)));
    for (size_t i = 0; i < state_.size(); ++i) state_[i] += w * (p[i] - state_[i]);
  }
  last_ns_ = t_ns;
  std::copy(state_.begin(), state_.end(), out.begin());
}

}  // namespace tlvlink::pipeline
