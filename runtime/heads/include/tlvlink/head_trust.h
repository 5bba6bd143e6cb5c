#pragma once
// Whether a head's predictions can be trusted, from the trust record the model file keeps for it
// (metadata.h HeadTrust: accuracy on a labelled test set and that set's majority-class rate).
// The board daemon leaves untrusted heads out of its default output; `tlvlink infer` and
// `tlvlink inspect` print the decision. Plain arithmetic: no allocation, no host dependency.
//
// The rule: a head is trusted when it beats always answering the commonest class of its own
// test set by more than noise explains,
//     accuracy - majority >= max(kMinTrustMargin, kTrustZ * sqrt(majority (1 - majority) / n)),
// i.e. by at least 2 points and by two binomial standard errors of the majority rate on n items
// (one-sided ~98 %). A head with no record is unmeasured, and not trusted. A record that also
// holds a baseline's accuracy on the same folds (a head fitted by `tlvlink heads fit --images`:
// logistic regression on the frame's pixels) must beat it too: a head no better than pixels
// reads nothing the encoder adds.
//
//   for (const LinearHead& h : model.metadata().linear_heads)
//     if (head_trusted(h.trust)) print(h.name, ...);

#include <cstdint>

#include "tlvlink/metadata.h"

namespace tlvlink {

inline constexpr double kMinTrustMargin = 0.02;  // 2 points over the majority class
inline constexpr double kTrustZ = 2.0;           // standard errors of the majority rate

enum class HeadTrustLevel : uint8_t {
  kUnmeasured = 0,  // no trust record
  kUntrusted,       // measured, not better than the majority class by the rule's margin
  kTrusted,
};

struct TrustAssessment {
  HeadTrustLevel level = HeadTrustLevel::kUnmeasured;
  double margin = 0;            // accuracy - majority (0 when unmeasured)
  double required = 0;          // the margin the rule asks for on this record's n
  bool below_baseline = false;  // the record's baseline did at least as well as the head
};

TrustAssessment assess_head(const HeadTrust& trust);
inline bool head_trusted(const HeadTrust& trust) {
  return assess_head(trust).level == HeadTrustLevel::kTrusted;
}
// "unmeasured", "untrusted", "trusted"
const char* head_trust_level_name(HeadTrustLevel level);

}  // namespace tlvlink
