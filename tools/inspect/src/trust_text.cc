#include "tlvlink/inspect/trust_text.h"

#include <cstdio>

#include "tlvlink/head_trust.h"

namespace tlvlink::inspect {

std::string trust_text(const HeadTrust& t, bool with_set) {
  const TrustAssessment a = assess_head(t);
  if (a.level == HeadTrustLevel::kUnmeasured) return "unmeasured: no test accuracy recorded";
  char buf[512];
  std::snprintf(buf, sizeof buf, "%s: test accuracy %.1f %% vs majority %.1f %% (n=%lld%s%.*s)",
                head_trust_level_name(a.level), 100.0 * static_cast<double>(t.accuracy),
                100.0 * static_cast<double>(t.majority), static_cast<long long>(t.n),
                with_set ? "; " : "", with_set ? static_cast<int>(t.test_set.size()) : 0,
                t.test_set.data());
  std::string text = buf;
  if (t.ci_low >= 0) {
    std::snprintf(buf, sizeof buf, "; 95 %% CI [%.1f, %.1f] %%",
                  100.0 * static_cast<double>(t.ci_low), 100.0 * static_cast<double>(t.ci_high));
    text += buf;
  }
  if (t.balanced_accuracy >= 0) {
    std::snprintf(buf, sizeof buf, "; balanced %.1f %%",
                  100.0 * static_cast<double>(t.balanced_accuracy));
    text += buf;
  }
  if (t.groups > 0) text += "; " + std::to_string(t.groups) + " groups";
  if (t.baseline_accuracy >= 0) {
    std::snprintf(buf, sizeof buf, "; baseline %.1f %% (%.*s)%s",
                  100.0 * static_cast<double>(t.baseline_accuracy),
                  static_cast<int>(t.baseline.size()), t.baseline.data(),
                  a.below_baseline ? ": the head does not beat it" : "");
    text += buf;
  }
  return text;
}

}  // namespace tlvlink::inspect
