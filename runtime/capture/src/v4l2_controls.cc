// Applying configured controls to an open device, by id or by v4l2-ctl key, with read-back.
#include <linux/videodev2.h>

#include <cstdio>
#include <cstring>

#include "v4l2_internal.h"

namespace tlvlink::capture::internal {
namespace {

// Finds a control by v4l2-ctl key among the controls the device offers; lists them if absent.
bool find_by_key(int fd, const char* key, v4l2_query_ext_ctrl& out, char* offered, size_t size) {
  size_t n = 0;
  offered[0] = '\0';
  v4l2_query_ext_ctrl q{};
  q.id = V4L2_CTRL_FLAG_NEXT_CTRL | V4L2_CTRL_FLAG_NEXT_COMPOUND;
  for (int guard = 0; guard < 1024 && xioctl(fd, VIDIOC_QUERY_EXT_CTRL, &q) == 0; ++guard) {
    if (q.type != V4L2_CTRL_TYPE_CTRL_CLASS) {
      char k[64];
      control_key(q.name, k, sizeof(k));
      if (std::strcmp(k, key) == 0) {
        out = q;
        return true;
      }
      if (n + 2 < size)
        n += static_cast<size_t>(std::snprintf(offered + n, size - n, "%s%s", n ? ", " : "", k));
    }
    q.id |= V4L2_CTRL_FLAG_NEXT_CTRL | V4L2_CTRL_FLAG_NEXT_COMPOUND;
  }
  return false;
}

Status apply_one(V4l2Source::State& s, const ControlSetting& c) {
  const char* key = c.name.c_str();
  v4l2_query_ext_ctrl q{};
  const uint32_t id = c.id ? c.id : well_known_control(c.name);
  if (id) {
    q.id = id;
    if (xioctl(s.fd, VIDIOC_QUERY_EXT_CTRL, &q) != 0 || (q.flags & V4L2_CTRL_FLAG_DISABLED)) {
      return Error::make(ErrorCode::kCaptureControl,
                         "%s: control '%s' (id 0x%08x) is not offered by the device", s.name, key,
                         id);
    }
  } else {
    char offered[200];
    if (!find_by_key(s.fd, key, q, offered, sizeof(offered))) {
      return Error::make(ErrorCode::kCaptureControl,
                         "%s: unknown control '%s' (the device offers: %s)", s.name, key,
                         offered[0] ? offered : "none");
    }
  }
  switch (q.type) {
    case V4L2_CTRL_TYPE_INTEGER:
    case V4L2_CTRL_TYPE_BOOLEAN:
    case V4L2_CTRL_TYPE_MENU:
    case V4L2_CTRL_TYPE_INTEGER_MENU:
    case V4L2_CTRL_TYPE_BUTTON:
    case V4L2_CTRL_TYPE_INTEGER64:
    case V4L2_CTRL_TYPE_BITMASK: break;
    default:
      return Error::make(ErrorCode::kCaptureControl,
                         "%s: control '%s' (%s) is not a numeric control", s.name, key, q.name);
  }
  if (q.flags & V4L2_CTRL_FLAG_READ_ONLY) {
    return Error::make(ErrorCode::kCaptureControl, "%s: control '%s' (%s) is read-only", s.name,
                       key, q.name);
  }
  if (q.type != V4L2_CTRL_TYPE_BUTTON && q.type != V4L2_CTRL_TYPE_BITMASK &&
      (c.value < q.minimum || c.value > q.maximum)) {
    return Error::make(ErrorCode::kCaptureControl,
                       "%s: control '%s' (%s) = %lld is outside [%lld, %lld]", s.name, key, q.name,
                       static_cast<long long>(c.value), static_cast<long long>(q.minimum),
                       static_cast<long long>(q.maximum));
  }
  v4l2_ext_control ctrl{};
  ctrl.id = q.id;
  if (q.type == V4L2_CTRL_TYPE_INTEGER64)
    ctrl.value64 = c.value;
  else
    ctrl.value = static_cast<int32_t>(c.value);
  v4l2_ext_controls set{};
  set.which = V4L2_CTRL_WHICH_CUR_VAL;
  set.count = 1;
  set.controls = &ctrl;
  if (int err = xioctl(s.fd, VIDIOC_S_EXT_CTRLS, &set); err != 0) {
    return Error::make(
        ErrorCode::kCaptureControl, "%s: setting control '%s' (%s) = %lld: %s%s", s.name, key,
        q.name, static_cast<long long>(c.value), std::strerror(err),
        err == EACCES ? " (an automatic mode governs it: set that mode to manual first)" : "");
  }
  AppliedControl applied{c.name, q.id, c.value};
  if (q.type != V4L2_CTRL_TYPE_BUTTON && !(q.flags & V4L2_CTRL_FLAG_WRITE_ONLY)) {
    ctrl = {};
    ctrl.id = q.id;
    if (xioctl(s.fd, VIDIOC_G_EXT_CTRLS, &set) == 0) {
      applied.value = q.type == V4L2_CTRL_TYPE_INTEGER64 ? ctrl.value64 : ctrl.value;
    }
  }
  s.applied.push_back(applied);
  return Status();
}

}  // namespace

Status apply_controls(V4l2Source::State& s) {
  s.applied.clear();
  for (const ControlSetting& c : s.config.controls) TLV_TRY(apply_one(s, c));
  return Status();
}

}  // namespace tlvlink::capture::internal
