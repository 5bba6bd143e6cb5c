#include "vivid/loop_feeder.h"

#include <fcntl.h>
#include <linux/v4l2-dv-timings.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "vivid/vivid_support.h"

namespace tlvlink::capture::vivid {
namespace {

uint32_t mix(uint32_t x) {  // a small integer hash: deterministic frame content per index
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

Error fail(const char* what, int err) {
  return Error::make(ErrorCode::kCapture, "vivid loop: %s: %s", what, std::strerror(err));
}

// Same DV timings on the capture input and the output: 640x480p59.94 (CEA-861).
Status set_timings(const std::string& dev, bool output) {
  const int fd = ::open(dev.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return fail(dev.c_str(), errno);
  int index = output ? 1 : 3;  // HDMI on both sides
  int err = xioctl(fd, output ? VIDIOC_S_OUTPUT : VIDIOC_S_INPUT, &index);
  v4l2_dv_timings t = V4L2_DV_BT_CEA_640X480P59_94;
  if (err == 0) err = xioctl(fd, VIDIOC_S_DV_TIMINGS, &t);
  ::close(fd);
  return err == 0 ? Status() : fail(output ? "output HDMI timings" : "capture HDMI timings", err);
}

}  // namespace

void frame_pattern(Pattern pattern, uint32_t index, std::span<uint8_t> out) {
  switch (pattern) {
    case Pattern::kIndexed:
      for (size_t i = 0; i < out.size(); ++i)
        out[i] = static_cast<uint8_t>(mix(index * 2654435761U + static_cast<uint32_t>(i / 4)) >>
                                      (8 * (i % 4)));
      break;
    case Pattern::kAllZero: std::memset(out.data(), 0, out.size()); break;
    case Pattern::kAllMax: std::memset(out.data(), 255, out.size()); break;
    case Pattern::kNoise:
      for (size_t i = 0; i < out.size(); ++i)
        out[i] = static_cast<uint8_t>(mix(0x5eed0000U ^ static_cast<uint32_t>(i)));
      break;
  }
  if (out.size() < 8) return;
  const uint32_t inv = ~index;
  std::memcpy(out.data(), &index, 4);
  std::memcpy(out.data() + 4, &inv, 4);
}

bool frame_index(std::span<const uint8_t> frame, uint32_t& index) {
  if (frame.size() < 8) return false;
  uint32_t inv = 0;
  std::memcpy(&index, frame.data(), 4);
  std::memcpy(&inv, frame.data() + 4, 4);
  return inv == ~index;
}

Result<std::unique_ptr<LoopFeeder>> LoopFeeder::start(const Nodes& nodes, image::PixelFormat format,
                                                      Pattern pattern) {
  return start(nodes, format, [pattern](uint32_t index, std::span<uint8_t> out) {
    frame_pattern(pattern, index, out);
  });
}

Result<std::unique_ptr<LoopFeeder>> LoopFeeder::start(const Nodes& nodes, image::PixelFormat format,
                                                      FrameFill fill) {
  if (nodes.output.empty())
    return Error::make(ErrorCode::kCaptureNoDevice, "vivid loop: no output node");
  TLV_TRY(set_timings(nodes.capture, false));
  TLV_TRY(set_timings(nodes.output, true));
  std::unique_ptr<LoopFeeder> f(new LoopFeeder());
  f->fill_ = std::move(fill);
  f->fd_ = ::open(nodes.output.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (f->fd_ < 0) return fail(nodes.output.c_str(), errno);
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  fmt.fmt.pix.width = kLoopWidth;
  fmt.fmt.pix.height = kLoopHeight;
  fmt.fmt.pix.pixelformat = image::pixel_format_fourcc(format);
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  if (int err = xioctl(f->fd_, VIDIOC_S_FMT, &fmt); err != 0) return fail("output S_FMT", err);
  if (fmt.fmt.pix.width != kLoopWidth || fmt.fmt.pix.height != kLoopHeight ||
      fmt.fmt.pix.pixelformat != image::pixel_format_fourcc(format)) {
    return Error::make(ErrorCode::kCaptureFormatRefused, "vivid loop: output set %ux%u",
                       fmt.fmt.pix.width, fmt.fmt.pix.height);
  }
  f->format_ = {format, kLoopWidth, kLoopHeight, static_cast<int32_t>(fmt.fmt.pix.bytesperline)};
  v4l2_requestbuffers req{};
  req.count = 4;
  req.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  req.memory = V4L2_MEMORY_MMAP;
  if (int err = xioctl(f->fd_, VIDIOC_REQBUFS, &req); err != 0) return fail("output REQBUFS", err);
  f->count_ = req.count < 4 ? req.count : 4;
  for (uint32_t i = 0; i < f->count_; ++i) {
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = i;
    if (int err = xioctl(f->fd_, VIDIOC_QUERYBUF, &b); err != 0)
      return fail("output QUERYBUF", err);
    void* p = ::mmap(nullptr, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, f->fd_, b.m.offset);
    if (p == MAP_FAILED) return fail("output mmap", errno);
    f->buffers_[i] = static_cast<uint8_t*>(p);
    f->lengths_[i] = b.length;
  }
  // Frame 0 in buffer 0; the others are queued as frames are fed.
  if (!f->queue_next()) return fail("output QBUF", errno);
  v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  if (int err = xioctl(f->fd_, VIDIOC_STREAMON, &type); err != 0)
    return fail("output STREAMON", err);
  f->thread_ = std::thread([p = f.get()] { p->run(); });
  return f;
}

bool LoopFeeder::queue_next() {
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  b.memory = V4L2_MEMORY_MMAP;
  const uint32_t index = next_index_.load();
  if (index < count_) {
    b.index = index;  // not queued yet
  } else if (xioctl(fd_, VIDIOC_DQBUF, &b) != 0) {
    return false;  // the output still holds every buffer: try again later
  }
  const size_t bytes = image::frame_bytes(format_);
  fill_(index, std::span(buffers_[b.index], bytes));
  b.bytesused = static_cast<uint32_t>(bytes);
  b.field = V4L2_FIELD_NONE;
  if (xioctl(fd_, VIDIOC_QBUF, &b) != 0) return false;
  next_index_.store(index + 1);
  return true;
}

void LoopFeeder::run() {
  auto next = std::chrono::steady_clock::now();
  while (!quit_.load()) {
    const int32_t ms = interval_ms_.load();
    if (ms <= 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      next = std::chrono::steady_clock::now();
      continue;
    }
    next += std::chrono::milliseconds(ms);
    std::this_thread::sleep_until(next);
    queue_next();
  }
}

void LoopFeeder::feed_every(int32_t interval_ms) { interval_ms_.store(interval_ms); }

void LoopFeeder::stop_output() {
  interval_ms_.store(0);
  v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  xioctl(fd_, VIDIOC_STREAMOFF, &type);
}

LoopFeeder::~LoopFeeder() {
  quit_.store(true);
  if (thread_.joinable()) thread_.join();
  if (fd_ >= 0) {
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    xioctl(fd_, VIDIOC_STREAMOFF, &type);
  }
  for (uint32_t i = 0; i < count_; ++i) {
    if (buffers_[i]) ::munmap(buffers_[i], lengths_[i]);
  }
  if (fd_ >= 0) {
    v4l2_requestbuffers req{};
    req.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    req.memory = V4L2_MEMORY_MMAP;
    xioctl(fd_, VIDIOC_REQBUFS, &req);
    ::close(fd_);
  }
}

}  // namespace tlvlink::capture::vivid
