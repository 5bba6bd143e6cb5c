#include "vivid/vivid_support.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>

namespace tlvlink::capture::vivid {
namespace {

std::string node_named(const std::string& wanted) {
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("/sys/class/video4linux", ec)) {
    std::ifstream f(e.path() / "name");
    std::string name;
    std::getline(f, name);
    if (name == wanted) return "/dev/" + e.path().filename().string();
  }
  return "";
}

// Finds a control id by key; 0 if absent.
uint32_t control_id(int fd, const char* key, uint32_t& type) {
  v4l2_query_ext_ctrl q{};
  q.id = V4L2_CTRL_FLAG_NEXT_CTRL | V4L2_CTRL_FLAG_NEXT_COMPOUND;
  while (xioctl(fd, VIDIOC_QUERY_EXT_CTRL, &q) == 0) {
    char k[64];
    control_key(q.name, k, sizeof(k));
    if (std::strcmp(k, key) == 0) {
      type = q.type;
      return q.id;
    }
    q.id |= V4L2_CTRL_FLAG_NEXT_CTRL | V4L2_CTRL_FLAG_NEXT_COMPOUND;
  }
  return 0;
}

int ext_ctrl(const std::string& dev, const char* key, int64_t& value, bool set) {
  const int fd = ::open(dev.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return errno;
  uint32_t type = 0;
  const uint32_t id = control_id(fd, key, type);
  int err = ENOENT;
  if (id != 0) {
    v4l2_ext_control c{};
    c.id = id;
    if (type == V4L2_CTRL_TYPE_INTEGER64)
      c.value64 = value;
    else
      c.value = static_cast<int32_t>(value);
    v4l2_ext_controls cs{};
    cs.which = V4L2_CTRL_WHICH_CUR_VAL;
    cs.count = 1;
    cs.controls = &c;
    err = xioctl(fd, set ? VIDIOC_S_EXT_CTRLS : VIDIOC_G_EXT_CTRLS, &cs);
    if (!set && err == 0) value = type == V4L2_CTRL_TYPE_INTEGER64 ? c.value64 : c.value;
  }
  ::close(fd);
  return err;
}

}  // namespace

int xioctl(int fd, unsigned long req, void* arg) {
  int rc;
  do rc = ::ioctl(fd, req, arg);
  while (rc < 0 && errno == EINTR);
  return rc < 0 ? errno : 0;
}

std::optional<Nodes> find_nodes() {
  Nodes n{node_named("vivid-000-vid-cap"), node_named("vivid-000-vid-out")};
  if (n.capture.empty()) return std::nullopt;
  return n;
}

std::string absent_reason() {
  return find_nodes() ? ""
                      : "vivid is not loaded (these tests run in the emulated board: "
                        "tools/setup/run_tests.sh board)";
}

bool in_rig() {
  const char* v = std::getenv("TLVLINK_RIG");
  return v != nullptr && std::strcmp(v, "1") == 0;
}

int set_control(const std::string& dev, const char* key, int64_t value) {
  return ext_ctrl(dev, key, value, true);
}

int get_control(const std::string& dev, const char* key, int64_t& value) {
  return ext_ctrl(dev, key, value, false);
}

int select_input(const std::string& dev, int input) {
  const int fd = ::open(dev.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return errno;
  int err = xioctl(fd, VIDIOC_S_INPUT, &input);
  ::close(fd);
  return err;
}

V4l2Config capture_config(const Nodes& nodes, image::PixelFormat format, int32_t width,
                          int32_t height, double fps) {
  V4l2Config c;
  c.label = "vivid";
  c.device.path = nodes.capture;
  c.format = format;
  c.width = width;
  c.height = height;
  c.fps = fps;
  c.watchdog_ms = 2000;
  c.backoff_initial_ms = 50;
  c.backoff_max_ms = 400;
  c.controls = parse_controls("osd_text_mode=2").value();  // no text drawn into the frames
  return c;
}

int64_t now_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

double cpu_seconds() {
  timespec ts{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

bool write_sysfs(const char* path, const char* text) {
  std::ofstream f(path);
  f << text;
  f.flush();
  return static_cast<bool>(f);
}

}  // namespace tlvlink::capture::vivid
