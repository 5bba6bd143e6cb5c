// Format, size and frame interval: ask, then read back what the driver actually set.
#include <linux/videodev2.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "v4l2_internal.h"

namespace tlvlink::capture::internal {
namespace {

// "yuyv, nv12, RGB3" — the formats the device offers, for an error message.
void offered_formats(int fd, char* out, size_t size) {
  size_t n = 0;
  out[0] = '\0';
  for (uint32_t i = 0; i < 64 && n + 8 < size; ++i) {
    v4l2_fmtdesc d{};
    d.index = i;
    d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(fd, VIDIOC_ENUM_FMT, &d) != 0) break;
    image::PixelFormat f;
    char fourcc[5] = {
        static_cast<char>(d.pixelformat & 0xFF), static_cast<char>((d.pixelformat >> 8) & 0xFF),
        static_cast<char>((d.pixelformat >> 16) & 0xFF), static_cast<char>(d.pixelformat >> 24), 0};
    const char* shown =
        image::pixel_format_from_fourcc(d.pixelformat, f) ? image::pixel_format_name(f) : fourcc;
    n += static_cast<size_t>(std::snprintf(out + n, size - n, "%s%s", n ? ", " : "", shown));
  }
}

Status set_interval(V4l2Source::State& s) {
  const char* name = s.name;
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (s.config.fps > 0) {
    if (int err = xioctl(s.fd, VIDIOC_G_PARM, &parm); err != 0) {
      return Error::make(ErrorCode::kCaptureFormatRefused,
                         "%s: cannot set %.2f fps: VIDIOC_G_PARM: %s", name, s.config.fps,
                         std::strerror(err));
    }
    if (!(parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME)) {
      return Error::make(ErrorCode::kCaptureFormatRefused,
                         "%s: the driver has no settable frame interval (asked for %.2f fps)", name,
                         s.config.fps);
    }
    // 1000 / (fps * 1000): the driver picks its nearest supported interval.
    parm.parm.capture.timeperframe.numerator = 1000;
    parm.parm.capture.timeperframe.denominator =
        static_cast<uint32_t>(std::lround(s.config.fps * 1000));
    if (int err = xioctl(s.fd, VIDIOC_S_PARM, &parm); err != 0) {
      return Error::make(ErrorCode::kCaptureFormatRefused, "%s: VIDIOC_S_PARM %.2f fps: %s", name,
                         s.config.fps, std::strerror(err));
    }
  }
  parm = {};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  s.stats.nominal_fps = 0;
  if (xioctl(s.fd, VIDIOC_G_PARM, &parm) == 0 && parm.parm.capture.timeperframe.numerator > 0) {
    const v4l2_fract& t = parm.parm.capture.timeperframe;
    s.stats.nominal_fps = static_cast<double>(t.denominator) / t.numerator;
  }
  return Status();
}

}  // namespace

Status negotiate(V4l2Source::State& s) {
  const V4l2Config& c = s.config;
  const uint32_t fourcc = image::pixel_format_fourcc(c.format);
  v4l2_format f{};
  f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  f.fmt.pix.width = static_cast<uint32_t>(c.width);
  f.fmt.pix.height = static_cast<uint32_t>(c.height);
  f.fmt.pix.pixelformat = fourcc;
  f.fmt.pix.field = V4L2_FIELD_NONE;
  if (int err = xioctl(s.fd, VIDIOC_S_FMT, &f); err != 0) {
    return Error::make(err == EBUSY ? ErrorCode::kCapture : ErrorCode::kCaptureFormatRefused,
                       "%s: VIDIOC_S_FMT %s %dx%d: %s%s", s.name,
                       image::pixel_format_name(c.format), c.width, c.height, std::strerror(err),
                       err == EBUSY ? " (another program is streaming from it)" : "");
  }
  f = {};
  f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (int err = xioctl(s.fd, VIDIOC_G_FMT, &f); err != 0) {
    return Error::make(ErrorCode::kCapture, "%s: VIDIOC_G_FMT: %s", s.name, std::strerror(err));
  }
  const v4l2_pix_format& p = f.fmt.pix;
  if (p.pixelformat != fourcc) {
    char offered[160];
    offered_formats(s.fd, offered, sizeof(offered));
    image::PixelFormat got;
    const bool known = image::pixel_format_from_fourcc(p.pixelformat, got);
    return Error::make(
        ErrorCode::kCaptureFormatRefused, "%s: asked for %s, the device set %s (it offers: %s)",
        s.name, image::pixel_format_name(c.format),
        known ? image::pixel_format_name(got) : "another format", offered[0] ? offered : "nothing");
  }
  if (static_cast<int32_t>(p.width) != c.width || static_cast<int32_t>(p.height) != c.height) {
    if (!c.accept_other_size) {
      return Error::make(ErrorCode::kCaptureFormatRefused,
                         "%s: asked for %s %dx%d, the device set %ux%u (it ignores the requested "
                         "size; accept_other_size uses what it delivers)",
                         s.name, image::pixel_format_name(c.format), c.width, c.height, p.width,
                         p.height);
    }
  }
  if (p.field != V4L2_FIELD_NONE && p.field != V4L2_FIELD_ANY) {
    return Error::make(
        ErrorCode::kCaptureFormatRefused,
        "%s: the device delivers interlaced fields (field %u); progressive frames only", s.name,
        p.field);
  }
  image::FrameFormat got{
      c.format, static_cast<int32_t>(p.width), static_cast<int32_t>(p.height),
      c.format == image::PixelFormat::kMjpeg ? 0 : static_cast<int32_t>(p.bytesperline)};
  if (c.format != image::PixelFormat::kMjpeg && p.sizeimage < image::frame_bytes(got)) {
    return Error::make(ErrorCode::kCaptureFormatRefused,
                       "%s: the driver's buffer size %u is below one %ux%u %s frame (%zu bytes)",
                       s.name, p.sizeimage, p.width, p.height, image::pixel_format_name(c.format),
                       image::frame_bytes(got));
  }
  if (s.format_fixed && (got.width != s.format.width || got.height != s.format.height ||
                         got.stride != s.format.stride)) {
    return Error::make(ErrorCode::kCaptureFormatRefused,
                       "%s: reopened with %dx%d (stride %d), first opened with %dx%d (stride %d)",
                       s.name, got.width, got.height, got.stride, s.format.width, s.format.height,
                       s.format.stride);
  }
  s.format = got;
  s.format_fixed = true;
  // After S_FMT: drivers may reset the interval when the format changes (vivid does).
  return set_interval(s);
}

}  // namespace tlvlink::capture::internal
