#pragma once
#ifndef TLVLINK_EXECUTOR_PRIVATE
#error \
    "define_ops.h is internal to runtime/executor: include the public tlvlink/... headers instead"
#endif
// Defines one model operator as XNNPACK node(s). The loader has validated shapes, dtypes and
// quantization, so these functions only translate; anything XNNPACK itself refuses comes back
// as a kBackend error naming the operator.

#include <cstdint>

#include "tlvlink/error.h"
#include "xnnpack/define_tensors.h"

namespace tlvlink::xnn {

// Dispatches on the operator type.
Status define_operator(ValueTable& values, int32_t op);

// define_conv.cc: Conv2D (dense, grouped, depthwise) and FullyConnected.
Status define_conv2d(ValueTable& values, int32_t op);
Status define_fully_connected(ValueTable& values, int32_t op);

}  // namespace tlvlink::xnn
