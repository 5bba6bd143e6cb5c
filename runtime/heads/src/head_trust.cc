// The head-trust rule (head_trust.h).

#include "tlvlink/head_trust.h"

#include <algorithm>
#include <cmath>

namespace tlvlink {

TrustAssessment assess_head(const HeadTrust& t) {
  TrustAssessment a;
  if (!t.present || t.n < 1) return a;
  const double majority = std::clamp(static_cast<double>(t.majority), 0.0, 1.0);
  const double accuracy = std::clamp(static_cast<double>(t.accuracy), 0.0, 1.0);
  a.margin = accuracy - majority;
  a.required = std::max(kMinTrustMargin,
                        kTrustZ * std::sqrt(majority * (1 - majority) / static_cast<double>(t.n)));
  a.below_baseline = t.baseline_accuracy >= 0 && t.accuracy <= t.baseline_accuracy;
  a.level = a.margin >= a.required && !a.below_baseline ? HeadTrustLevel::kTrusted
                                                        : HeadTrustLevel::kUntrusted;
  return a;
}

const char* head_trust_level_name(HeadTrustLevel level) {
  switch (level) {
    case HeadTrustLevel::kUnmeasured: return "unmeasured";
    case HeadTrustLevel::kUntrusted: return "untrusted";
    case HeadTrustLevel::kTrusted: return "trusted";
  }
  return "?";
}

}  // namespace tlvlink
