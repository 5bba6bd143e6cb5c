// Which USB device is the board (usb_host.h); no libusb here, so it is tested everywhere.
#include <charconv>
#include <cstdio>
#include <string>

#include "tlvlink/listen/usb_host.h"

namespace tlvlink::listen {
namespace {

Result<uint16_t> hex16(std::string_view s, std::string_view text) {
  unsigned v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v, 16);
  TLV_ENSURE(!s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size() && v <= 0xFFFF,
             ErrorCode::kInvalidArgument,
             "usb '%.*s': '%.*s' is not a 4-digit hex id (VID:PID, e.g. 1d6b:0104)",
             static_cast<int>(text.size()), text.data(), static_cast<int>(s.size()), s.data());
  return static_cast<uint16_t>(v);
}

std::string describe(const UsbCandidate& c) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "%04x:%04x on bus %u address %u, serial '%s'", c.vendor,
                c.product, c.bus, c.address, c.serial.c_str());
  return buf;
}

}  // namespace

Result<UsbSelector> parse_usb_selector(std::string_view text) {
  UsbSelector s;
  std::string_view ids = text.substr(0, text.find(','));
  if (!ids.empty()) {
    const size_t colon = ids.find(':');
    TLV_ENSURE(colon != std::string_view::npos, ErrorCode::kInvalidArgument,
               "usb '%.*s': expected VID:PID (e.g. 1d6b:0104)", static_cast<int>(text.size()),
               text.data());
    TLV_ASSIGN_OR_RETURN(s.vendor, hex16(ids.substr(0, colon), text));
    TLV_ASSIGN_OR_RETURN(s.product, hex16(ids.substr(colon + 1), text));
  }
  for (size_t at = text.find(','); at != std::string_view::npos;) {
    const size_t end = text.find(',', at + 1);
    const std::string_view opt =
        text.substr(at + 1, end == std::string_view::npos ? std::string_view::npos : end - at - 1);
    TLV_ENSURE(opt.substr(0, 7) == "serial=", ErrorCode::kInvalidArgument,
               "usb '%.*s': unknown option '%.*s' (serial=S)", static_cast<int>(text.size()),
               text.data(), static_cast<int>(opt.size()), opt.data());
    s.serial = std::string(opt.substr(7));
    at = end;
  }
  return s;
}

Result<size_t> select_usb_device(std::span<const UsbCandidate> found, const UsbSelector& want) {
  std::string seen;
  size_t chosen = found.size(), matches = 0;
  for (size_t i = 0; i < found.size(); ++i) {
    const UsbCandidate& c = found[i];
    if (c.vendor != want.vendor || c.product != want.product) continue;
    if (!seen.empty()) seen += "; ";
    seen += describe(c);
    if (!c.accessible) {
      seen += " (no permission: install the udev rule or run as root)";
      continue;
    }
    if (!want.serial.empty() && c.serial != want.serial) continue;
    if (!c.has_stream_interface) {
      seen += " (no tlvlink stream interface: is tlvlinkd running with output \"usb\"?)";
      continue;
    }
    chosen = i;
    ++matches;
  }
  if (matches == 1) return chosen;
  char head[96];
  std::snprintf(head, sizeof(head), "USB %04x:%04x%s%s", want.vendor, want.product,
                want.serial.empty() ? "" : " serial ", want.serial.c_str());
  if (matches > 1) {
    return Error::make(ErrorCode::kInvalidArgument,
                       "%s: %zu boards match (%s); choose one with serial=", head, matches,
                       seen.c_str());
  }
  return Error::make(ErrorCode::kTransportUnavailable,
                     "%s: no board with the stream interface found%s%s", head,
                     seen.empty() ? "" : "; seen: ", seen.c_str());
}

}  // namespace tlvlink::listen
