#pragma once
// The step-indexed schedules of a training run: the curriculum weight beta of TLV-Link
// (x = beta * x_vision + (1 - beta) * x_touch) and the learning rate (linear warm-up, cosine
// decay). Pure functions of the step, so a resumed run recomputes exactly what it would have used.

#include <cstdint>
#include <string>
#include <string_view>

#include "tlvlink/error.h"

namespace tlvlink::trainer {

enum class BetaSchedule : uint8_t { kLinear, kExponential, kCosine, kNone };
const char* beta_schedule_name(BetaSchedule s);  // "linear", "exponential", "cosine", "none"
Result<BetaSchedule> parse_beta_schedule(std::string_view name);

// Decay rate of the exponential schedule: beta falls as exp(-k t) over the span, rescaled so it
// starts at beta1 and reaches beta_min exactly at the end of the span (t = 1). k = 5 leaves
// exp(-5) = 0.7 % of the decay for the last instant, so the rescaling barely bends the curve.
inline constexpr double kExponentialBetaRate = 5.0;

struct BetaOptions {
  BetaSchedule schedule = BetaSchedule::kLinear;  // kNone: beta = 0 at every step (ablation)
  double beta1 = 0.9;                             // beta at step 0, in [0, 1]
  double span = 0.9;      // fraction of all steps over which beta decays, in (0, 1]
  double beta_min = 0.0;  // beta from the end of the span on, in [0, beta1]
};
Status validate(const BetaOptions& options);

// beta at `step` of `total_steps`. With t = step / round(span * total_steps):
//   linear       beta1 + (beta_min - beta1) t
//   cosine       beta_min + (beta1 - beta_min) (1 + cos(pi t)) / 2
//   exponential  beta_min + (beta1 - beta_min) (exp(-k t) - exp(-k)) / (1 - exp(-k))
// and beta_min for t >= 1.
double beta_at(const BetaOptions& options, int64_t step, int64_t total_steps);

struct LrOptions {
  double lr = 2e-4;  // peak learning rate
  int64_t warmup_steps = 200;
  double min_lr = 0.0;  // floor of the cosine decay
};
Status validate(const LrOptions& options);

// Linear warm-up from lr / warmup_steps at step 0 to lr at step warmup_steps - 1, then cosine
// decay from lr to min_lr at the last step (total_steps - 1). When total_steps <= warmup_steps
// the warm-up is shortened to total_steps / 10 (at least 1 step) and that is the rule, stated.
double lr_at(const LrOptions& options, int64_t step, int64_t total_steps);
int64_t effective_warmup(const LrOptions& options, int64_t total_steps);

}  // namespace tlvlink::trainer
