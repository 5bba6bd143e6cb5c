// Parsing and describing device selectors ("usb:VID:PID[:SERIAL]" or a path).
#include <cstdio>
#include <string>

#include "tlvlink/capture/device_select.h"

namespace tlvlink::capture {
namespace {

bool parse_hex16(std::string_view text, uint16_t& out) {
  if (text.size() != 4) return false;
  uint32_t v = 0;
  for (char c : text) {
    v <<= 4;
    if (c >= '0' && c <= '9')
      v |= static_cast<uint32_t>(c - '0');
    else if (c >= 'a' && c <= 'f')
      v |= static_cast<uint32_t>(c - 'a' + 10);
    else if (c >= 'A' && c <= 'F')
      v |= static_cast<uint32_t>(c - 'A' + 10);
    else
      return false;
  }
  out = static_cast<uint16_t>(v);
  return true;
}

}  // namespace

Result<DeviceSelector> parse_device_selector(std::string_view text) {
  DeviceSelector sel;
  const std::string shown(text);
  if (text.starts_with("path:")) text.remove_prefix(5);
  if (text.starts_with("/")) {
    sel.path = std::string(text);
    return sel;
  }
  if (text.starts_with("usb:")) {
    std::string_view rest = text.substr(4);
    const size_t c1 = rest.find(':');
    const std::string_view vid = rest.substr(0, c1);
    std::string_view after =
        c1 == std::string_view::npos ? std::string_view() : rest.substr(c1 + 1);
    const size_t c2 = after.find(':');
    const std::string_view pid = after.substr(0, c2);
    if (c1 != std::string_view::npos && parse_hex16(vid, sel.vendor_id) &&
        parse_hex16(pid, sel.product_id) && (sel.vendor_id != 0 || sel.product_id != 0)) {
      if (c2 != std::string_view::npos) sel.serial = std::string(after.substr(c2 + 1));
      if (c2 == std::string_view::npos || !sel.serial.empty()) return sel;
    }
  }
  return Error::make(ErrorCode::kInvalidArgument,
                     "device '%s': expected usb:VID:PID, usb:VID:PID:SERIAL (VID/PID as 4 hex "
                     "digits, e.g. usb:0c45:636d) or a device path such as /dev/video0",
                     shown.c_str());
}

std::string describe_selector(const DeviceSelector& sel) {
  if (!sel.path.empty()) return "path " + sel.path;
  char ids[32];
  std::snprintf(ids, sizeof(ids), "usb %04x:%04x", sel.vendor_id, sel.product_id);
  return std::string(ids) + (sel.serial.empty() ? " (any serial)" : " serial " + sel.serial);
}

}  // namespace tlvlink::capture
