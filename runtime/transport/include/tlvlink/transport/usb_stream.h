#pragma once
// How the stream travels over USB bulk, shared by the board (FunctionFS, ffs.h) and the host
// (libusb, tools/listen): which interface carries it and how bytes are cut into transfers.
//
// The board's function is one vendor-specific interface (class 0xFF, subclass 0x54 'T',
// protocol 0x01) with one bulk IN and one bulk OUT endpoint; the host finds it by these numbers
// (its interface number and endpoint addresses depend on the other functions of the gadget, e.g.
// a CDC-ACM beside it). The byte stream is the same COBS-framed stream as on a serial line.
//
// Transfers: each direction sends at most kUsbMaxTransfer bytes per transfer and the reader
// reads with a buffer of kUsbMaxTransfer. A transfer whose length is a multiple of kUsbPadMultiple
// (the largest full-speed packet; every high- and super-speed size is a multiple of it) gets one
// 0x00 appended, so it always ends with a short packet and completes at once on the other side
// (a read larger than a transfer that ends on a full packet would wait for more). A 0x00 between
// frames is an empty frame: readers ignore it.

#include <cstddef>
#include <cstdint>

namespace tlvlink::transport {

inline constexpr uint8_t kUsbInterfaceClass = 0xFF;     // vendor specific
inline constexpr uint8_t kUsbInterfaceSubclass = 0x54;  // 'T'
inline constexpr uint8_t kUsbInterfaceProtocol = 0x01;  // tlvlink stream, protocol major 1
inline constexpr size_t kUsbMaxTransfer = 16384;
inline constexpr size_t kUsbPadMultiple = 64;
inline constexpr uint16_t kUsbFullSpeedPacket = 64;
inline constexpr uint16_t kUsbHighSpeedPacket = 512;
// Development default ids (Linux Foundation, "Multifunction Composite Gadget"): a product sets its
// own.
inline constexpr uint16_t kUsbDefaultVendor = 0x1d6b;
inline constexpr uint16_t kUsbDefaultProduct = 0x0104;

// Bytes of `available` that one transfer takes (leaving room for the pad byte).
constexpr size_t usb_chunk(size_t available) {
  return available < kUsbMaxTransfer - 1 ? available : kUsbMaxTransfer - 1;
}
// Whether a transfer of `n` bytes needs the 0x00 pad byte.
constexpr bool usb_needs_pad(size_t n) { return n > 0 && n % kUsbPadMultiple == 0; }

}  // namespace tlvlink::transport
