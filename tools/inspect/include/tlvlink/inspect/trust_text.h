#pragma once
// How `tlvlink inspect` and `tlvlink infer` show a head's trust record (runtime/heads
// head_trust.h).
//
//   trust_text(head.trust)         // "trusted: test accuracy 82.0 % vs majority 73.4 % (n=2160;
//   touch: DIR ...)" trust_text(head.trust, false)  // the same without the set

#include <string>

#include "tlvlink/metadata.h"

namespace tlvlink::inspect {

// "unmeasured: no test accuracy recorded" when the head has no record.
std::string trust_text(const HeadTrust& trust, bool with_set = true);

}  // namespace tlvlink::inspect
