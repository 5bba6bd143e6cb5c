// Finding a V4L2 capture node by USB identity (sysfs) or by path.
#include <dirent.h>
#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <string>

#include "tlvlink/capture/device_select.h"

namespace tlvlink::capture {
namespace {

std::string read_line(const std::string& path) {
  std::string out;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return out;
  char buf[256];
  const ssize_t n = ::read(fd, buf, sizeof(buf) - 1);
  ::close(fd);
  if (n <= 0) return out;
  out.assign(buf, static_cast<size_t>(n));
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  return out;
}

bool exists(const std::string& path) { return ::access(path.c_str(), F_OK) == 0; }

std::string real_path(const std::string& path) {
  char buf[PATH_MAX];
  return ::realpath(path.c_str(), buf) ? std::string(buf) : std::string();
}

// The USB device above a video4linux node: the closest ancestor of its "device" link holding
// idVendor/idProduct (a UVC node's device is the interface, e.g. .../1-1/1-1:1.0).
void read_usb_identity(const std::string& node_dir, const std::string& sysfs_root,
                       DeviceInfo& info) {
  std::string dir = real_path(node_dir + "/device");
  const std::string root = real_path(sysfs_root);
  for (int depth = 0; depth < 8 && !dir.empty() && dir.size() > root.size(); ++depth) {
    if (exists(dir + "/idVendor") && exists(dir + "/idProduct")) {
      info.vendor_id =
          static_cast<uint16_t>(std::strtoul(read_line(dir + "/idVendor").c_str(), nullptr, 16));
      info.product_id =
          static_cast<uint16_t>(std::strtoul(read_line(dir + "/idProduct").c_str(), nullptr, 16));
      info.serial = read_line(dir + "/serial");
      info.usb_port = dir.substr(dir.rfind('/') + 1);
      return;
    }
    dir = dir.substr(0, dir.rfind('/'));
  }
}

// "video10" after "video9".
bool node_less(const DeviceInfo& a, const DeviceInfo& b) {
  if (a.node.size() != b.node.size()) return a.node.size() < b.node.size();
  return a.node < b.node;
}

Result<uint32_t> caps_of(const DeviceRoots& roots, const std::string& path) {
  return roots.query_caps ? roots.query_caps(path.c_str(), roots.user)
                          : query_v4l2_caps(path.c_str());
}

DeviceInfo describe_node(const DeviceRoots& roots, const std::string& node) {
  DeviceInfo info;
  const std::string dir = roots.sysfs + "/class/video4linux/" + node;
  info.node = node;
  info.path = roots.dev + "/" + node;
  info.name = read_line(dir + "/name");
  read_usb_identity(dir, roots.sysfs, info);
  auto caps = caps_of(roots, info.path);
  info.device_caps = caps.ok() ? *caps : 0;
  return info;
}

std::string summary(const DeviceInfo& d) {
  char buf[160];
  if (d.vendor_id != 0 || d.product_id != 0) {
    std::snprintf(buf, sizeof(buf), "%s %04x:%04x SN '%s' '%s'%s", d.node.c_str(), d.vendor_id,
                  d.product_id, d.serial.c_str(), d.name.c_str(),
                  d.can_capture() ? "" : " (no capture)");
  } else {
    std::snprintf(buf, sizeof(buf), "%s '%s'%s", d.node.c_str(), d.name.c_str(),
                  d.can_capture() ? "" : " (no capture)");
  }
  return buf;
}

Result<DeviceInfo> find_by_path(const DeviceSelector& sel, const DeviceRoots& roots) {
  const std::string real = real_path(sel.path);
  if (real.empty()) {
    return Error::make(ErrorCode::kCaptureNoDevice, "%s: no such device (%s)", sel.path.c_str(),
                       std::strerror(errno));
  }
  DeviceInfo info;
  const std::string node = real.substr(real.rfind('/') + 1);
  if (exists(roots.sysfs + "/class/video4linux/" + node)) {
    info = describe_node(roots, node);
  }
  info.path = real;
  info.node = node;
  TLV_ASSIGN_OR_RETURN(info.device_caps, caps_of(roots, real));
  if (!info.can_capture()) {
    return Error::make(
        ErrorCode::kCaptureNotCamera,
        "%s ('%s') is not a video capture node with streaming (device_caps 0x%08x%s)",
        sel.path.c_str(), info.name.c_str(), info.device_caps,
        (info.device_caps & V4L2_CAP_META_CAPTURE) ? ": a metadata node" : "");
  }
  return info;
}

}  // namespace

bool DeviceInfo::can_capture() const {
  return (device_caps & V4L2_CAP_VIDEO_CAPTURE) && (device_caps & V4L2_CAP_STREAMING);
}

Result<uint32_t> query_v4l2_caps(const char* dev_path) {
  const int fd = ::open(dev_path, O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    return Error::make(err == ENOENT || err == ENODEV || err == ENXIO ? ErrorCode::kCaptureNoDevice
                                                                      : ErrorCode::kCapture,
                       "%s: open: %s", dev_path, std::strerror(err));
  }
  v4l2_capability cap{};
  int rc;
  do rc = ::ioctl(fd, VIDIOC_QUERYCAP, &cap);
  while (rc < 0 && errno == EINTR);
  const int err = errno;
  ::close(fd);
  if (rc < 0) {
    // ENOTTY: the node has no such ioctl. ENOSYS: the same from an emulator (qemu-user passes
    // only the ioctls it knows).
    const bool not_v4l2 = err == ENOTTY || err == ENOSYS;
    return Error::make(not_v4l2 ? ErrorCode::kCaptureNotCamera : ErrorCode::kCapture,
                       "%s: VIDIOC_QUERYCAP: %s%s", dev_path, std::strerror(err),
                       not_v4l2 ? " (not a V4L2 device)" : "");
  }
  return (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
}

std::vector<DeviceInfo> list_v4l2_devices(const DeviceRoots& roots) {
  std::vector<DeviceInfo> out;
  DIR* dir = ::opendir((roots.sysfs + "/class/video4linux").c_str());
  if (!dir) return out;
  while (const dirent* e = ::readdir(dir)) {
    if (std::strncmp(e->d_name, "video", 5) == 0) out.push_back(describe_node(roots, e->d_name));
  }
  ::closedir(dir);
  std::sort(out.begin(), out.end(), node_less);
  return out;
}

Result<DeviceInfo> find_v4l2_device(const DeviceSelector& sel, const DeviceRoots& roots) {
  if (!sel.path.empty()) return find_by_path(sel, roots);
  const std::string wanted = describe_selector(sel);
  const std::vector<DeviceInfo> all = list_v4l2_devices(roots);
  std::vector<const DeviceInfo*> matching, capture;
  for (const DeviceInfo& d : all) {
    if (d.vendor_id != sel.vendor_id || d.product_id != sel.product_id) continue;
    if (!sel.serial.empty() && d.serial != sel.serial) continue;
    matching.push_back(&d);
    if (d.can_capture()) capture.push_back(&d);
  }
  if (capture.empty()) {
    // Say what is there: the matching non-capture nodes, or every node when nothing matched.
    std::string present;
    if (matching.empty()) {
      for (const DeviceInfo& d : all) present += (present.empty() ? "" : "; ") + summary(d);
    } else {
      for (const DeviceInfo* d : matching) present += (present.empty() ? "" : "; ") + summary(*d);
    }
    if (!matching.empty()) {
      return Error::make(ErrorCode::kCaptureNotCamera,
                         "%s: only nodes that cannot capture video: %s", wanted.c_str(),
                         present.c_str());
    }
    return Error::make(ErrorCode::kCaptureNoDevice, "no camera matches %s; present: %s",
                       wanted.c_str(), present.empty() ? "no video devices" : present.c_str());
  }
  // Several capture nodes of one camera (same port): the first. Several cameras: ambiguous.
  for (const DeviceInfo* d : capture) {
    if (d->usb_port != capture.front()->usb_port) {
      std::string which;
      for (const DeviceInfo* c : capture) {
        which += (which.empty() ? "" : ", ") + ("'" + c->serial + "' (" + c->node + ")");
      }
      return Error::make(ErrorCode::kInvalidArgument,
                         "%zu cameras match %s: serials %s; add the serial (usb:VID:PID:SERIAL)",
                         capture.size(), wanted.c_str(), which.c_str());
    }
  }
  return *capture.front();
}

}  // namespace tlvlink::capture
