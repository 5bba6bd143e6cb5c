// mmap streaming buffers: request, map (read-only), queue; and undo.
#include <linux/videodev2.h>
#include <sys/mman.h>

#include <cstring>

#include "v4l2_internal.h"

namespace tlvlink::capture::internal {

Status map_buffers(V4l2Source::State& s) {
  v4l2_requestbuffers req{};
  req.count = s.config.buffers;
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (int err = xioctl(s.fd, VIDIOC_REQBUFS, &req); err != 0) {
    return Error::make(err == EINVAL ? ErrorCode::kCaptureFormatRefused : ErrorCode::kCapture,
                       "%s: VIDIOC_REQBUFS %u mmap buffers: %s%s", s.name, s.config.buffers,
                       std::strerror(err), err == EINVAL ? " (no mmap streaming)" : "");
  }
  if (req.count < kMinBuffers || req.count > kMaxGrantedBuffers) {
    return Error::make(ErrorCode::kCaptureFormatRefused,
                       "%s: asked for %u buffers, the driver granted %u (usable: %u..%u)", s.name,
                       s.config.buffers, req.count, kMinBuffers, kMaxGrantedBuffers);
  }
  s.buffer_count = req.count;
  for (uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = i;
    if (int err = xioctl(s.fd, VIDIOC_QUERYBUF, &b); err != 0) {
      return Error::make(ErrorCode::kCapture, "%s: VIDIOC_QUERYBUF %u: %s", s.name, i,
                         std::strerror(err));
    }
    void* p = ::mmap(nullptr, b.length, PROT_READ, MAP_SHARED, s.fd, b.m.offset);
    if (p == MAP_FAILED) {
      return Error::make(ErrorCode::kCapture, "%s: mmap of buffer %u (%u bytes): %s", s.name, i,
                         b.length, std::strerror(errno));
    }
    s.buffers[i] = {static_cast<const uint8_t*>(p), b.length};
    if (int err = xioctl(s.fd, VIDIOC_QBUF, &b); err != 0) {
      return Error::make(ErrorCode::kCapture, "%s: VIDIOC_QBUF %u: %s", s.name, i,
                         std::strerror(err));
    }
  }
  return Status();
}

void unmap_buffers(V4l2Source::State& s) {
  for (uint32_t i = 0; i < kMaxGrantedBuffers; ++i) {
    if (s.buffers[i].data) ::munmap(const_cast<uint8_t*>(s.buffers[i].data), s.buffers[i].length);
    s.buffers[i] = {};
  }
  if (s.fd >= 0 && s.buffer_count > 0) {
    v4l2_requestbuffers req{};  // frees the driver's buffers; fails harmlessly on a gone device
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    xioctl(s.fd, VIDIOC_REQBUFS, &req);
  }
  s.buffer_count = 0;
  s.held = -1;
}

}  // namespace tlvlink::capture::internal
