#pragma once
// Temporal smoothing of a head's per-frame probabilities while one object is in contact: an
// exponential average with time constant tau over the frames' capture times,
//   p <- p + (1 - exp(-dt / tau)) (p_frame - p),
// restarted at every contact onset (a new touch may be a new object). tau = 0 turns it off. The
// smoothed probabilities still sum to 1. No allocation after create().

#include <cstdint>
#include <span>
#include <vector>

namespace tlvlink::pipeline {

class ProbabilitySmoother {
 public:
  ProbabilitySmoother() = default;
  ProbabilitySmoother(int32_t labels, int64_t tau_ns);

  // Restart from the next frame (contact onset).
  void restart() { started_ = false; }
  // Adds one frame's probabilities at t_ns and writes the smoothed ones to `out` (labels values).
  void add(std::span<const float> probabilities, int64_t t_ns, std::span<float> out);

 private:
  std::vector<float> state_;
  int64_t tau_ns_ = 0, last_ns_ = 0;
  bool started_ = false;
};

}  // namespace tlvlink::pipeline
