#pragma once
// USB bulk on the board through FunctionFS (built with TLVLINK_WITH_USB). The gadget is set up
// by scripts/usb_gadget.sh (configfs + `mount -t functionfs`); this transport writes the
// function's descriptors and strings to ep0 (FunctionFS v2 descriptors: full and high speed,
// one bulk IN + one bulk OUT, usb_stream.h's interface numbers), opens ep1 (IN) and ep2 (OUT)
// and, if `udc` and `gadget` are given and writable, binds the gadget itself. The link is up
// while the host has the function enabled (FUNCTIONFS_ENABLE); unbind, disable or unplug is a
// disconnect and open() is retried until the host enables it again. I/O is Linux AIO on the
// endpoint files (raw syscalls: no libaio) completing into an eventfd, so waits have timeouts
// and can be interrupted.

#include <cstddef>
#include <memory>
#include <span>
#include <string>

#include "tlvlink/error.h"
#include "tlvlink/transport/transport.h"

namespace tlvlink::transport {

struct FfsConfig {
  std::string dir = "/dev/ffs-tlvlink";  // where functionfs is mounted
  std::string udc;                       // e.g. "dummy_udc.0"; empty: bound by usb_gadget.sh
  std::string gadget;  // configfs gadget dir, e.g. /sys/kernel/config/usb_gadget/tlvlink
};

Result<std::unique_ptr<Transport>> make_ffs_transport(const FfsConfig& config);

// The bytes written to ep0: descriptors (FunctionFS v2 format) and strings. Exposed for tests
// and for the specification. Return the size written into `out` (256 bytes always suffice).
size_t ffs_descriptors(std::span<std::byte> out);
size_t ffs_strings(std::span<std::byte> out);

}  // namespace tlvlink::transport
