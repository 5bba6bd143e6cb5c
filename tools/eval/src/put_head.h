#pragma once
#ifndef TLVLINK_EVAL_PRIVATE
#error "put_head.h is internal to tools/eval: include its public headers instead"
#endif
// A fitted head into a model's head list: the one of the same name is replaced, else it is
// added (user_head.cc, press_head.cc).

#include <algorithm>
#include <vector>

#include "tlvlink/quantize/model_builder.h"

namespace tlvlink::eval {

// True when a head of that name was replaced.
inline bool put_head(std::vector<quantize::LinearHeadSpec>& heads,
                     const quantize::LinearHeadSpec& head) {
  auto same = std::find_if(heads.begin(), heads.end(),
                           [&](const quantize::LinearHeadSpec& h) { return h.name == head.name; });
  if (same == heads.end()) {
    heads.push_back(head);
    return false;
  }
  *same = head;
  return true;
}

}  // namespace tlvlink::eval
