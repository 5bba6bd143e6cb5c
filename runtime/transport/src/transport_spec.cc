// make_transport("serial:/dev/ttyGS0,baud=115200") and friends (transport_spec.h).
#include "tlvlink/transport/transport_spec.h"

#include <charconv>
#include <string>
#include <vector>

#include "tlvlink/transport/pty.h"
#include "tlvlink/transport/serial.h"
#include "usb_factory.h"

namespace tlvlink::transport {
namespace {

struct Spec {
  std::string scheme, path;
  std::vector<std::pair<std::string, std::string>> options;
};

Result<Spec> parse(std::string_view text) {
  Spec spec;
  const size_t colon = text.find(':');
  const size_t comma = text.find(',');
  const size_t scheme_end = std::min(colon, comma);
  spec.scheme = std::string(text.substr(0, scheme_end));
  if (scheme_end == std::string_view::npos) return spec;
  std::string_view rest = text.substr(scheme_end + (scheme_end == colon ? 1 : 0));
  const size_t first_comma = rest.find(',');
  spec.path = std::string(rest.substr(0, first_comma));
  while (first_comma != std::string_view::npos && !rest.empty()) {
    rest = rest.substr(rest.find(',') + 1);
    const std::string_view item = rest.substr(0, rest.find(','));
    const size_t eq = item.find('=');
    TLV_ENSURE(eq != std::string_view::npos && eq > 0, ErrorCode::kInvalidArgument,
               "link '%.*s': option '%.*s' is not key=value", static_cast<int>(text.size()),
               text.data(), static_cast<int>(item.size()), item.data());
    spec.options.emplace_back(std::string(item.substr(0, eq)), std::string(item.substr(eq + 1)));
    if (rest.find(',') == std::string_view::npos) break;
  }
  return spec;
}

Result<std::unique_ptr<Transport>> make_serial(std::string_view text, const Spec& spec) {
  SerialConfig config;
  config.path = spec.path;
  for (const auto& [key, value] : spec.options) {
    if (key == "baud") {
      int baud = 0;
      const auto r = std::from_chars(value.data(), value.data() + value.size(), baud);
      TLV_ENSURE(r.ec == std::errc() && r.ptr == value.data() + value.size(),
                 ErrorCode::kInvalidArgument, "link '%.*s': baud '%s' is not a number",
                 static_cast<int>(text.size()), text.data(), value.c_str());
      config.baud = baud;
    } else if (key == "flow") {
      TLV_ENSURE(value == "none" || value == "rtscts", ErrorCode::kInvalidArgument,
                 "link '%.*s': flow '%s' is not none or rtscts", static_cast<int>(text.size()),
                 text.data(), value.c_str());
      config.flow = value == "rtscts" ? FlowControl::kRtsCts : FlowControl::kNone;
    } else {
      return Error::make(ErrorCode::kInvalidArgument,
                         "link '%.*s': unknown option '%s' (serial takes baud, flow)",
                         static_cast<int>(text.size()), text.data(), key.c_str());
    }
  }
  return make_serial_transport(config);
}

}  // namespace

Result<std::unique_ptr<Transport>> make_transport(std::string_view text) {
  TLV_ASSIGN_OR_RETURN(Spec spec, parse(text));
  if (spec.scheme == "serial") {
    TLV_ENSURE(!spec.path.empty(), ErrorCode::kInvalidArgument,
               "link '%.*s': serial needs a device path (serial:/dev/ttyGS0)",
               static_cast<int>(text.size()), text.data());
    return make_serial(text, spec);
  }
  if (spec.scheme == "pty") {
    TLV_ENSURE(spec.options.empty(), ErrorCode::kInvalidArgument,
               "link '%.*s': pty takes no options", static_cast<int>(text.size()), text.data());
    if (Status st = check_pty_link(spec.path); !st.ok()) return st.error();
    return std::unique_ptr<Transport>(std::make_unique<PtyTransport>(PtyConfig{spec.path}));
  }
  if (spec.scheme == "usb") {
    std::string udc, gadget;
    for (const auto& [key, value] : spec.options) {
      if (key == "udc")
        udc = value;
      else if (key == "gadget")
        gadget = value;
      else
        return Error::make(ErrorCode::kInvalidArgument,
                           "link '%.*s': unknown option '%s' (usb takes udc, gadget)",
                           static_cast<int>(text.size()), text.data(), key.c_str());
    }
    return internal::make_usb_device_transport(spec.path.empty() ? "/dev/ffs-tlvlink" : spec.path,
                                               udc, gadget);
  }
  return Error::make(ErrorCode::kInvalidArgument,
                     "link '%.*s': unknown kind '%s' (serial:PATH, pty:LINK, usb[:FFS_DIR])",
                     static_cast<int>(text.size()), text.data(), spec.scheme.c_str());
}

}  // namespace tlvlink::transport
