#pragma once
#ifndef TLVLINK_EVAL_PRIVATE
#error "parallel_items.h is internal to tools/eval: include its public headers instead"
#endif
// Independent items on up to N threads (the caller's among them), results placed by item by the
// caller's work function, so that they are the same for any N.

#include <cstddef>
#include <cstdint>
#include <functional>

#include "tlvlink/error.h"

namespace tlvlink::eval::internal {

using ItemWork = std::function<Status(size_t item, int32_t worker)>;
// work(i, w) for every i in [0, n) on min(threads, n) threads, w in [0, threads) the one running
// it; items are taken in order, and after a failure no further one is started. Returns the
// failure of the lowest item.
Status run_items(size_t n, int32_t threads, const ItemWork& work);

}  // namespace tlvlink::eval::internal
