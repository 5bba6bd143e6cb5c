// Built when TLVLINK_WITH_USB is OFF: `usb` links explain how to get them.
#include "usb_factory.h"

namespace tlvlink::transport::internal {

Result<std::unique_ptr<Transport>> make_usb_device_transport(const std::string&, const std::string&,
                                                             const std::string&) {
  return Error(
      ErrorCode::kInvalidArgument,
      "this build has no USB transport: configure with -DTLVLINK_WITH_USB=ON (FunctionFS)");
}

}  // namespace tlvlink::transport::internal
