#pragma once
#ifndef TLVLINK_EXECUTOR_PRIVATE
#error "status.h is internal to runtime/executor: include the public tlvlink/... headers instead"
#endif
// XNNPACK status -> tlvlink Error. XNNPACK has no logging, so the status code is all it says;
// the message adds which node we were defining or running and which call refused.

#include "tlvlink/error.h"
#include "xnnpack/xnn_api.h"

namespace tlvlink::xnn {

// "xnn_status_invalid_parameter" etc.; "xnn_status_<n>" for a code this build does not know.
const char* status_name(int status);

// A short hint for the statuses whose meaning is not obvious from the name, or "".
const char* status_hint(int status);

// Error kBackend: "operator 'stem' (#0): xnn_define_convolution_2d failed: xnn_status_... (2)".
Error backend_error(int status, const char* call, const NodeRef& who);

}  // namespace tlvlink::xnn
