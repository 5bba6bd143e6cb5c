#pragma once
// The USB device-side transport for make_transport(): FunctionFS when built with
// TLVLINK_WITH_USB (ffs_transport.cc), otherwise an error saying so (usb_absent.cc).
#ifndef TLVLINK_TRANSPORT_PRIVATE
#error "usb_factory.h is internal to tlvlink_transport"
#endif

#include <memory>
#include <string>

#include "tlvlink/error.h"
#include "tlvlink/transport/transport.h"

namespace tlvlink::transport::internal {

Result<std::unique_ptr<Transport>> make_usb_device_transport(const std::string& ffs_dir,
                                                             const std::string& udc,
                                                             const std::string& gadget);

}  // namespace tlvlink::transport::internal
