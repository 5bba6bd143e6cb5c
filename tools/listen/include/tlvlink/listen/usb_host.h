#pragma once
// The host side of USB bulk: finding the board's stream interface (tlvlink/transport/
// usb_stream.h) by VID:PID and USB serial, and a libusb transport on it (built with
// TLVLINK_WITH_USB and libusb-1.0). Re-enumerates on every open(), so a board that is unplugged
// and plugged back (or whose gadget is unbound and bound again) is found again; that works with
// or without udev (the emulated board has none).

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "tlvlink/error.h"
#include "tlvlink/transport/transport.h"
#include "tlvlink/transport/usb_stream.h"

namespace tlvlink::listen {

struct UsbSelector {
  uint16_t vendor = transport::kUsbDefaultVendor;
  uint16_t product = transport::kUsbDefaultProduct;
  std::string serial;  // empty: any
};

// "", "1d6b:0104", "1d6b:0104,serial=ABC", ",serial=ABC".
Result<UsbSelector> parse_usb_selector(std::string_view text);

// What enumeration found: one entry per device with the selector's VID:PID.
struct UsbCandidate {
  uint16_t vendor = 0, product = 0;
  std::string serial;  // empty if it could not be read
  uint8_t bus = 0, address = 0;
  bool has_stream_interface = false;
  bool accessible = true;  // false: could not be opened (permissions: udev rule missing)
};

// Index of the one device to use; kTransportUnavailable naming what was found otherwise
// (nothing, wrong serials, no stream interface, no permission), kInvalidArgument when several
// match and no serial chooses between them.
Result<size_t> select_usb_device(std::span<const UsbCandidate> found, const UsbSelector& want);

Result<std::unique_ptr<transport::Transport>> make_usb_host_transport(const UsbSelector& selector);

}  // namespace tlvlink::listen
