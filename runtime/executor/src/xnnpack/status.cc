#include "xnnpack/status.h"

#include <xnnpack.h>

namespace tlvlink::xnn {

const char* status_name(int status) {
  switch (static_cast<xnn_status>(status)) {
    case xnn_status_success: return "xnn_status_success";
    case xnn_status_uninitialized: return "xnn_status_uninitialized";
    case xnn_status_invalid_parameter: return "xnn_status_invalid_parameter";
    case xnn_status_invalid_state: return "xnn_status_invalid_state";
    case xnn_status_unsupported_parameter: return "xnn_status_unsupported_parameter";
    case xnn_status_unsupported_hardware: return "xnn_status_unsupported_hardware";
    case xnn_status_out_of_memory: return "xnn_status_out_of_memory";
  }
  return "xnn_status_unknown";
}

const char* status_hint(int status) {
  switch (static_cast<xnn_status>(status)) {
    case xnn_status_invalid_parameter:
      return " (shape, datatype or quantization combination this XNNPACK does not accept)";
    case xnn_status_unsupported_parameter:
      return " (valid, but outside what this XNNPACK implements, e.g. a requantization scale "
             "ratio out of range)";
    case xnn_status_unsupported_hardware: return " (CPU lacks the required instruction set)";
    default: return "";
  }
}

Error backend_error(int status, const char* call, const NodeRef& who) {
  if (who.index >= 0) {
    return Error::make(ErrorCode::kBackend, "%s '%.*s' (#%d): %s failed: %s (%d)%s", who.kind,
                       static_cast<int>(who.name.size()), who.name.data(), who.index, call,
                       status_name(status), status, status_hint(status));
  }
  return Error::make(ErrorCode::kBackend, "%s: %s failed: %s (%d)%s", who.kind, call,
                     status_name(status), status, status_hint(status));
}

}  // namespace tlvlink::xnn
