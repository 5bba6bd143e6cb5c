#pragma once
// How `tlvlink infer` and `tlvlink inspect` show a head's trust record (head_trust.h).

#include <string>

#include "tlvlink/head_trust.h"
#include "tlvlink/metadata.h"

namespace tlvlink::cli {

// "trusted: test accuracy 82.0 % vs majority 73.4 % (n=2160; touch: DIR ...)" or
// "unmeasured: no test accuracy recorded".
std::string trust_text(const HeadTrust& trust, bool with_set = true);

}  // namespace tlvlink::cli
