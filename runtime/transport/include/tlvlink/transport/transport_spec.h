#pragma once
// A link named by one configuration string, as the daemon's `output` key gives it:
//   serial:PATH[,baud=N][,flow=none|rtscts]   UART, CDC-ACM (/dev/ttyGS0), a pty slave
//   pty:LINK                                  a new pty; LINK becomes a symlink to its slave
//   usb[:FFS_DIR][,udc=NAME][,gadget=DIR]     USB bulk through FunctionFS (builds with
//                                             TLVLINK_WITH_USB); FFS_DIR defaults to
//                                             /dev/ffs-tlvlink
// Errors name the part of the string that is wrong.

#include <memory>
#include <string_view>

#include "tlvlink/error.h"
#include "tlvlink/transport/transport.h"

namespace tlvlink::transport {

Result<std::unique_ptr<Transport>> make_transport(std::string_view spec);

}  // namespace tlvlink::transport
