// Built without TLVLINK_WITH_USB: `usb` sources explain how to get them.
#include "tlvlink/listen/usb_host.h"

namespace tlvlink::listen {

Result<std::unique_ptr<transport::Transport>> make_usb_host_transport(const UsbSelector&) {
  return Error(ErrorCode::kInvalidArgument,
               "this build has no USB host transport: configure with -DTLVLINK_WITH_USB=ON (needs "
               "libusb-1.0-0-dev)");
}

}  // namespace tlvlink::listen
