#pragma once
// Finding a camera by identity: USB vendor:product id and serial number read from sysfs, never a
// /dev/videoN index (indices change with plug order and with other cameras present). Nodes that
// cannot capture video (a UVC camera's metadata node, output nodes) are skipped. An explicit
// device path exists for test drivers such as vivid, which have no USB identity.
//
//   auto sel = parse_device_selector("usb:0c45:636d:2BDF-Q7KX");
//   auto dev = find_v4l2_device(*sel);   // DeviceInfo{path "/dev/video2", ...} or an error
//                                        // naming what matched and what did not

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::capture {

struct DeviceSelector {
  uint16_t vendor_id = 0;   // USB idVendor; 0 with product_id 0: select by path
  uint16_t product_id = 0;  // USB idProduct
  std::string serial;       // USB serial; empty: any, allowed only when exactly one device matches
  std::string path;         // explicit node (/dev/video0, /dev/v4l/by-id/...): test devices
};

// Accepted forms: "usb:VID:PID", "usb:VID:PID:SERIAL" (VID/PID 4 hex digits), "/dev/...",
// "path:/dev/...". The error names the text and the expected forms.
Result<DeviceSelector> parse_device_selector(std::string_view text);
// "usb 0c45:636d serial 2BDF-Q7KX", "usb 2833:0209 (any serial)", "path /dev/video0".
std::string describe_selector(const DeviceSelector& selector);

// One video4linux node.
struct DeviceInfo {
  std::string path;        // /dev/videoN (dev root + node)
  std::string node;        // videoN
  std::string name;        // the driver's name for it (sysfs "name", e.g. "GelSight Mini R0B ...")
  uint16_t vendor_id = 0;  // 0 when the node has no USB device above it
  uint16_t product_id = 0;
  std::string serial;        // USB serial ("" if none)
  std::string usb_port;      // sysfs USB device, e.g. "1-1.2": where it is plugged in
  uint32_t device_caps = 0;  // V4L2 device_caps (VIDIOC_QUERYCAP); 0 if it could not be read
  bool can_capture() const;  // V4L2_CAP_VIDEO_CAPTURE and V4L2_CAP_STREAMING
};

// Where devices are looked up. Tests point the roots at a fake tree and substitute query_caps.
struct DeviceRoots {
  std::string sysfs = "/sys";
  std::string dev = "/dev";
  // Reads the device_caps of a node; nullptr: open it and ask (VIDIOC_QUERYCAP).
  Result<uint32_t> (*query_caps)(const char* dev_path, void* user) = nullptr;
  void* user = nullptr;
};

// Every node under <sysfs>/class/video4linux, sorted by node name. A node whose caps cannot be
// read is listed with device_caps 0.
std::vector<DeviceInfo> list_v4l2_devices(const DeviceRoots& roots = {});

// The one capture node matching the selector. Errors: kCaptureNoDevice (nothing matches: the
// message lists the cameras that are present), kCaptureNotCamera (only non-capture nodes match,
// or the explicit path is not a capture node), kInvalidArgument (several devices match and no
// serial was given: the message lists their serials).
Result<DeviceInfo> find_v4l2_device(const DeviceSelector& selector, const DeviceRoots& roots = {});

// VIDIOC_QUERYCAP on a node (device_caps when the driver reports them, else capabilities).
Result<uint32_t> query_v4l2_caps(const char* dev_path);

}  // namespace tlvlink::capture
