// discordance: where two evaluations of the same test items disagree, and whether a coin could.

#include <algorithm>
#include <cmath>

#include "tlvlink/eval/eval.h"

namespace tlvlink::eval {
namespace {

// Exact two-sided binomial test of k successes in n trials at p = 1/2, min(1, 2 P(X <= k)),
// summed in log space so n in the tens of thousands does not underflow a term.
double two_sided_half_binomial(int64_t k, int64_t n) {
  if (n == 0) return 1.0;
  const double ln_half_n = static_cast<double>(n) * std::log(0.5);
  const double ln_n_fact = std::lgamma(static_cast<double>(n) + 1.0);
  double tail = 0;
  for (int64_t i = 0; i <= k; ++i) {
    tail += std::exp(ln_n_fact - std::lgamma(static_cast<double>(i) + 1.0) -
                     std::lgamma(static_cast<double>(n - i) + 1.0) + ln_half_n);
  }
  return std::min(1.0, 2.0 * tail);
}

}  // namespace

Result<Discordance> discordance(const TaskResult& first, const TaskResult& second) {
  TLV_ENSURE(first.task == second.task, ErrorCode::kInvalidArgument,
             "comparing the %s cell with the %s cell", task_name(first.task),
             task_name(second.task));
  TLV_ENSURE(first.available && second.available, ErrorCode::kInvalidArgument,
             "%s: a cell was not evaluated", task_name(first.task));
  TLV_ENSURE(first.item_correct.size() == second.item_correct.size() &&
                 first.item_correct.size() == static_cast<size_t>(first.n),
             ErrorCode::kInvalidArgument,
             "%s: the cells scored different test items (%zu vs %zu per-item results, n %lld)",
             task_name(first.task), first.item_correct.size(), second.item_correct.size(),
             static_cast<long long>(first.n));
  Discordance d;
  for (size_t i = 0; i < first.item_correct.size(); ++i) {
    if (first.item_correct[i] != 0 && second.item_correct[i] == 0) ++d.only_first;
    if (first.item_correct[i] == 0 && second.item_correct[i] != 0) ++d.only_second;
  }
  d.p =
      two_sided_half_binomial(std::min(d.only_first, d.only_second), d.only_first + d.only_second);
  return d;
}

}  // namespace tlvlink::eval
