#pragma once
// Serial links through termios: a UART (/dev/ttyAMA0), USB CDC-ACM (/dev/ttyGS0 on the board,
// /dev/ttyACM0 on the host) or a pty slave. Raw 8N1; baud rate and flow control from the
// configuration. A device that is absent at open() or goes away later (unplug, gadget unbind,
// pty master closed) is reported so the caller reopens it when it returns.

#include <memory>
#include <string>

#include "tlvlink/error.h"
#include "tlvlink/transport/transport.h"

namespace tlvlink::transport {

enum class FlowControl : uint8_t { kNone = 0, kRtsCts = 1 };

struct SerialConfig {
  std::string path;  // e.g. /dev/ttyGS0, or a udev /dev/serial/by-id/... link
  int baud = 0;      // 0: leave as is (CDC-ACM and ptys ignore it)
  FlowControl flow = FlowControl::kNone;
};

// Standard rates 1200 ... 4000000; kInvalidArgument for others (checked here, not at open()).
Result<std::unique_ptr<Transport>> make_serial_transport(const SerialConfig& config);

}  // namespace tlvlink::transport
