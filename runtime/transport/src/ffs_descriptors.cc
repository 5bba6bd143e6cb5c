// The FunctionFS descriptor and string blobs (linux/usb/functionfs.h, v2 format).
#include <endian.h>
#include <linux/usb/ch9.h>
#include <linux/usb/functionfs.h>

#include <cstring>

#include "tlvlink/transport/ffs.h"
#include "tlvlink/transport/usb_stream.h"

namespace tlvlink::transport {
namespace {

struct __attribute__((packed)) SpeedDescriptors {
  usb_interface_descriptor interface;
  usb_endpoint_descriptor_no_audio in;   // ep1: board -> host
  usb_endpoint_descriptor_no_audio out;  // ep2: host -> board
};

struct __attribute__((packed)) Descriptors {
  usb_functionfs_descs_head_v2 header;
  __le32 fs_count;
  __le32 hs_count;
  SpeedDescriptors fs, hs;
};

SpeedDescriptors speed(uint16_t packet) {
  SpeedDescriptors d{};
  d.interface.bLength = USB_DT_INTERFACE_SIZE;
  d.interface.bDescriptorType = USB_DT_INTERFACE;
  d.interface.bNumEndpoints = 2;
  d.interface.bInterfaceClass = kUsbInterfaceClass;
  d.interface.bInterfaceSubClass = kUsbInterfaceSubclass;
  d.interface.bInterfaceProtocol = kUsbInterfaceProtocol;
  d.interface.iInterface = 1;
  for (auto* ep : {&d.in, &d.out}) {
    ep->bLength = USB_DT_ENDPOINT_SIZE;
    ep->bDescriptorType = USB_DT_ENDPOINT;
    ep->bmAttributes = USB_ENDPOINT_XFER_BULK;
    ep->wMaxPacketSize = htole16(packet);
  }
  d.in.bEndpointAddress = 1 | USB_DIR_IN;
  d.out.bEndpointAddress = 2 | USB_DIR_OUT;
  return d;
}

constexpr char kInterfaceName[] = "tlvlink stream";

struct __attribute__((packed)) Strings {
  usb_functionfs_strings_head header;
  __le16 language;
  char name[sizeof(kInterfaceName)];
};

}  // namespace

size_t ffs_descriptors(std::span<std::byte> out) {
  Descriptors d{};
  d.header.magic = htole32(FUNCTIONFS_DESCRIPTORS_MAGIC_V2);
  d.header.flags = htole32(FUNCTIONFS_HAS_FS_DESC | FUNCTIONFS_HAS_HS_DESC);
  d.header.length = htole32(sizeof(d));
  d.fs_count = htole32(3);
  d.hs_count = htole32(3);
  d.fs = speed(kUsbFullSpeedPacket);
  d.hs = speed(kUsbHighSpeedPacket);
  if (out.size() < sizeof(d)) return 0;
  std::memcpy(out.data(), &d, sizeof(d));
  return sizeof(d);
}

size_t ffs_strings(std::span<std::byte> out) {
  Strings s{};
  s.header.magic = htole32(FUNCTIONFS_STRINGS_MAGIC);
  s.header.length = htole32(sizeof(s));
  s.header.str_count = htole32(1);
  s.header.lang_count = htole32(1);
  s.language = htole16(0x0409);  // en-US
  std::memcpy(s.name, kInterfaceName, sizeof(kInterfaceName));
  if (out.size() < sizeof(s)) return 0;
  std::memcpy(out.data(), &s, sizeof(s));
  return sizeof(s);
}

}  // namespace tlvlink::transport
