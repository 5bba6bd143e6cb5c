// beta and learning-rate schedules.

#include "tlvlink/trainer/schedule.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tlvlink::trainer {

const char* beta_schedule_name(BetaSchedule s) {
  switch (s) {
    case BetaSchedule::kLinear: return "linear";
    case BetaSchedule::kExponential: return "exponential";
    case BetaSchedule::kCosine: return "cosine";
    case BetaSchedule::kNone: return "none";
  }
  return "?";
}

Result<BetaSchedule> parse_beta_schedule(std::string_view name) {
  for (BetaSchedule s : {BetaSchedule::kLinear, BetaSchedule::kExponential, BetaSchedule::kCosine,
                         BetaSchedule::kNone}) {
    if (name == beta_schedule_name(s)) return s;
  }
  return Error::make(ErrorCode::kInvalidArgument,
                     "unknown beta schedule '%.*s' (linear, exponential, cosine, none)",
                     static_cast<int>(name.size()), name.data());
}

Status validate(const BetaOptions& o) {
  TLV_ENSURE(o.beta1 >= 0 && o.beta1 <= 1, ErrorCode::kInvalidArgument, "beta1 %g outside [0, 1]",
             o.beta1);
  TLV_ENSURE(o.span > 0 && o.span <= 1, ErrorCode::kInvalidArgument,
             "beta span %g outside (0, 1] (a fraction of all steps)", o.span);
  TLV_ENSURE(o.beta_min >= 0 && o.beta_min <= o.beta1, ErrorCode::kInvalidArgument,
             "beta-min %g outside [0, beta1 = %g]", o.beta_min, o.beta1);
  return {};
}

double beta_at(const BetaOptions& o, int64_t step, int64_t total_steps) {
  if (o.schedule == BetaSchedule::kNone) return 0.0;
  const auto span_steps = std::max<int64_t>(
      1, std::llround(o.span * static_cast<double>(std::max<int64_t>(total_steps, 1))));
  const double t =
      static_cast<double>(std::max<int64_t>(step, 0)) / static_cast<double>(span_steps);
  if (t >= 1.0) return o.beta_min;
  const double range = o.beta1 - o.beta_min;
  switch (o.schedule) {
    case BetaSchedule::kLinear: return o.beta1 - range * t;
    case BetaSchedule::kCosine:
      return o.beta_min + range * 0.5 * (1.0 + std::cos(std::numbers::pi * t));
    case BetaSchedule::kExponential: {
      const double k = kExponentialBetaRate;
      return o.beta_min + range * (std::exp(-k * t) - std::exp(-k)) / (1.0 - std::exp(-k));
    }
    case BetaSchedule::kNone: break;
  }
  return 0.0;
}

Status validate(const LrOptions& o) {
  TLV_ENSURE(o.lr > 0 && o.lr < 1, ErrorCode::kInvalidArgument, "learning rate %g outside (0, 1)",
             o.lr);
  TLV_ENSURE(o.warmup_steps >= 0, ErrorCode::kInvalidArgument, "warm-up steps %lld < 0",
             static_cast<long long>(o.warmup_steps));
  TLV_ENSURE(o.min_lr >= 0 && o.min_lr <= o.lr, ErrorCode::kInvalidArgument,
             "minimum learning rate %g outside [0, lr = %g]", o.min_lr, o.lr);
  return {};
}

int64_t effective_warmup(const LrOptions& o, int64_t total_steps) {
  if (o.warmup_steps < total_steps) return o.warmup_steps;
  return std::max<int64_t>(1, total_steps / 10);
}

double lr_at(const LrOptions& o, int64_t step, int64_t total_steps) {
  const int64_t warmup = effective_warmup(o, total_steps);
  if (step < warmup) {
    return o.lr * static_cast<double>(step + 1) / static_cast<double>(warmup);
  }
  const int64_t decay_steps = total_steps - 1 - warmup;
  if (decay_steps <= 0) return o.lr;
  const double t =
      std::clamp(static_cast<double>(step - warmup) / static_cast<double>(decay_steps), 0.0, 1.0);
  return o.min_lr + (o.lr - o.min_lr) * 0.5 * (1.0 + std::cos(std::numbers::pi * t));
}

}  // namespace tlvlink::trainer
