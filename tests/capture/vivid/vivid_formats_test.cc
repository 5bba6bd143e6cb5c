// Negotiation against a real V4L2 driver (vivid's webcam input): formats and sizes, the frame
// interval (S_PARM after S_FMT, read back), sizes the device does not offer, no MJPEG, and
// device selection on the real sysfs.
#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "tlvlink/capture/v4l2_source.h"
#include "vivid/vivid_support.h"

namespace tlvlink::capture {
namespace {

using image::PixelFormat;

class VividWebcam : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto reason = vivid::absent_reason(); !reason.empty()) GTEST_SKIP() << reason;
    nodes = *vivid::find_nodes();
    ASSERT_EQ(vivid::select_input(nodes.capture, 0), 0);  // webcam input
  }

  // Starts a source and checks n frames against the negotiated format.
  void stream(V4l2Source& src, int n) {
    int64_t last_ts = 0;
    uint64_t last_seq = 0;
    for (int i = 0; i < n; ++i) {
      auto f = src.next(3000);
      ASSERT_TRUE(f.ok()) << f.error().message();
      EXPECT_EQ(f->bytes.size(), image::frame_bytes(src.format()));
      EXPECT_EQ(f->format.width, src.format().width);
      if (i > 0) {
        EXPECT_GT(f->timestamp_ns, last_ts);
        EXPECT_GT(f->sequence, last_seq);
      }
      last_ts = f->timestamp_ns;
      last_seq = f->sequence;
      src.release();
    }
  }

  vivid::Nodes nodes;
};

TEST_F(VividWebcam, FormatsAndSizes) {
  struct Case {
    PixelFormat format;
    int32_t w, h;
  } cases[] = {
      {PixelFormat::kYuyv, 320, 180},  {PixelFormat::kYuyv, 640, 360},
      {PixelFormat::kYuyv, 1280, 720}, {PixelFormat::kNv12, 320, 180},
      {PixelFormat::kNv12, 640, 360},  {PixelFormat::kRgb24, 320, 180},
      {PixelFormat::kRgb24, 640, 360}, {PixelFormat::kGrey, 320, 180},
      {PixelFormat::kGrey, 640, 480},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(image::pixel_format_name(c.format)) + " " + std::to_string(c.w) + "x" +
                 std::to_string(c.h));
    auto src = make_v4l2_source(vivid::capture_config(nodes, c.format, c.w, c.h, 0));
    ASSERT_TRUE(src.ok());
    Status s = (*src)->start();
    ASSERT_TRUE(s.ok()) << s.error().message();
    EXPECT_EQ((*src)->format().format, c.format);
    EXPECT_EQ((*src)->format().width, c.w);
    EXPECT_EQ((*src)->format().height, c.h);
    EXPECT_GE((*src)->format().stride, c.format == PixelFormat::kYuyv ? 2 * c.w : c.w);
    EXPECT_GE((*src)->buffer_bytes(), image::frame_bytes((*src)->format()));
    EXPECT_EQ((*src)->buffer_count(), 4u);
    stream(**src, 3);
    EXPECT_TRUE((*src)->stats().driver_timestamps);  // vivid stamps CLOCK_MONOTONIC
    std::printf("note: %s %dx%d: stride %d, %zu bytes, %.2f fps nominal\n",
                image::pixel_format_name(c.format), c.w, c.h, (*src)->format().stride,
                image::frame_bytes((*src)->format()), (*src)->stats().nominal_fps);
  }
}

// The frame interval depends on the size (vivid's webcam: 60 fps at 320x180, 12.5 at 1280x720)
// and S_FMT moves it, so an interval set before the format is not what streams.
double interval_fps(int fd) {
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (::ioctl(fd, VIDIOC_G_PARM, &parm) != 0) return -1;
  return static_cast<double>(parm.parm.capture.timeperframe.denominator) /
         parm.parm.capture.timeperframe.numerator;
}

int set_size(int fd, uint32_t w, uint32_t h) {
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (::ioctl(fd, VIDIOC_G_FMT, &fmt) != 0) return -1;
  fmt.fmt.pix.width = w;
  fmt.fmt.pix.height = h;
  fmt.fmt.pix.pixelformat = V4L2_PIX_FMT_YUYV;
  return ::ioctl(fd, VIDIOC_S_FMT, &fmt);
}

TEST_F(VividWebcam, IntervalIsSetAfterFormatAndReadBack) {
  const int fd = ::open(nodes.capture.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(set_size(fd, 320, 180), 0);
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  parm.parm.capture.timeperframe = {1, 60};
  ASSERT_EQ(::ioctl(fd, VIDIOC_S_PARM, &parm), 0);
  const double set = interval_fps(fd);
  ASSERT_EQ(set_size(fd, 1280, 720), 0);
  const double after_big = interval_fps(fd);
  ASSERT_EQ(set_size(fd, 320, 180), 0);
  const double after_back = interval_fps(fd);
  ::close(fd);
  std::printf(
      "note: vivid: S_PARM 60 fps at 320x180 -> %.2f; S_FMT 1280x720 -> %.2f; S_FMT 320x180 -> "
      "%.2f\n",
      set, after_big, after_back);
  EXPECT_DOUBLE_EQ(set, 60.0);
  EXPECT_LT(after_big, 60.0);
  EXPECT_LT(after_back, 60.0) << "S_FMT changed the interval; only S_PARM after S_FMT sets it";

  // The source sets the interval after the format and reports what the driver read back.
  auto src = make_v4l2_source(vivid::capture_config(nodes, PixelFormat::kYuyv, 320, 180, 60));
  ASSERT_TRUE((*src)->start().ok());
  EXPECT_DOUBLE_EQ((*src)->stats().nominal_fps, 60.0);
  (*src)->stop();
  auto src25 = make_v4l2_source(vivid::capture_config(nodes, PixelFormat::kYuyv, 640, 360, 25));
  ASSERT_TRUE((*src25)->start().ok());
  EXPECT_DOUBLE_EQ((*src25)->stats().nominal_fps, 25.0);
  stream(**src25, 30);
  const double measured = (*src25)->stats().measured_fps;
  std::printf("note: 640x360 asked 25 fps: nominal %.2f, measured from timestamps %.2f\n",
              (*src25)->stats().nominal_fps, measured);
  // vivid paces frames by jiffies; a loaded host stalls the emulated CPUs now and then.
  EXPECT_NEAR(measured, 25.0, 4.0);
  (*src25)->stop();

  // A rate the size does not offer: the driver's nearest is reported, not the request.
  auto big = make_v4l2_source(vivid::capture_config(nodes, PixelFormat::kYuyv, 1280, 720, 30));
  Status st = (*big)->start();
  ASSERT_TRUE(st.ok()) << st.error().message();
  std::printf("note: 1280x720 asked 30 fps: the driver set %.2f\n", (*big)->stats().nominal_fps);
  EXPECT_GT((*big)->stats().nominal_fps, 0);
  EXPECT_LT((*big)->stats().nominal_fps, 30.0);
}

TEST_F(VividWebcam, SizeTheDeviceDoesNotOffer) {
  auto src = make_v4l2_source(vivid::capture_config(nodes, PixelFormat::kYuyv, 333, 222, 0));
  Status s = (*src)->start();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kCaptureFormatRefused);
  const std::string msg = s.error().message();
  EXPECT_NE(msg.find("asked for yuyv 333x222, the device set"), std::string::npos) << msg;
  std::printf("note: %s\n", msg.c_str());

  auto cfg = vivid::capture_config(nodes, PixelFormat::kYuyv, 333, 222, 0);
  cfg.accept_other_size = true;
  auto accepting = make_v4l2_source(cfg);
  ASSERT_TRUE((*accepting)->start().ok());
  const image::FrameFormat real = (*accepting)->format();
  EXPECT_TRUE(real.width != 333 || real.height != 222);
  auto f = (*accepting)->next(3000);
  ASSERT_TRUE(f.ok()) << f.error().message();
  EXPECT_EQ(f->format.width, real.width);
  EXPECT_EQ(f->bytes.size(), image::frame_bytes(real));
  std::printf("note: accepted: the device delivers %dx%d\n", real.width, real.height);
}

TEST_F(VividWebcam, HasNoMjpeg) {
  const int fd = ::open(nodes.capture.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  int formats = 0;
  bool mjpeg = false;
  v4l2_fmtdesc d{};
  d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  for (; ::ioctl(fd, VIDIOC_ENUM_FMT, &d) == 0; ++d.index) {
    ++formats;
    mjpeg |= d.pixelformat == V4L2_PIX_FMT_MJPEG || d.pixelformat == V4L2_PIX_FMT_JPEG;
  }
  ::close(fd);
  std::printf("note: vivid offers %d capture formats, MJPEG: %s\n", formats, mjpeg ? "yes" : "no");
  EXPECT_GT(formats, 10);
  EXPECT_FALSE(mjpeg);  // so MJPEG error handling is tested by injection (capture_mjpeg_test)

  auto src = make_v4l2_source(vivid::capture_config(nodes, PixelFormat::kMjpeg, 640, 360, 0));
  Status s = (*src)->start();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kCaptureFormatRefused);
  EXPECT_NE(std::string(s.error().message()).find("asked for mjpeg, the device set"),
            std::string::npos)
      << s.error().message();
}

TEST_F(VividWebcam, SelectionOnTheRealSysfs) {
  const auto all = list_v4l2_devices();
  int capture = 0, output = 0;
  for (const DeviceInfo& d : all) {
    std::printf("note: %s '%s' caps 0x%08x\n", d.path.c_str(), d.name.c_str(), d.device_caps);
    if (d.name == "vivid-000-vid-cap") {
      ++capture;
      EXPECT_TRUE(d.can_capture());
    }
    if (d.name == "vivid-000-vid-out") {
      ++output;
      EXPECT_FALSE(d.can_capture());
    }
  }
  EXPECT_EQ(capture, 1);
  EXPECT_LE(output, 1);
  // The output node is not a camera; a USB identity that is not plugged in is absent.
  if (!nodes.output.empty()) {
    DeviceSelector out;
    out.path = nodes.output;
    EXPECT_EQ(find_v4l2_device(out).error().code(), ErrorCode::kCaptureNotCamera);
  }
  auto mini = find_v4l2_device(parse_device_selector("usb:0c45:636d").value());
  ASSERT_FALSE(mini.ok());
  EXPECT_EQ(mini.error().code(), ErrorCode::kCaptureNoDevice);
  EXPECT_NE(std::string(mini.error().message()).find("vivid-000-vid-cap"), std::string::npos)
      << mini.error().message();
}

TEST_F(VividWebcam, UnknownControlIsNamed) {
  auto cfg = vivid::capture_config(nodes, PixelFormat::kYuyv, 320, 180, 0);
  cfg.controls = parse_controls("brightness=10, led_intensity=5").value();
  auto src = make_v4l2_source(cfg);
  Status s = (*src)->start();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kCaptureControl);
  EXPECT_NE(std::string(s.error().message()).find("unknown control 'led_intensity'"),
            std::string::npos)
      << s.error().message();
  cfg.controls = parse_controls("brightness=300").value();
  auto range = make_v4l2_source(cfg);
  s = (*range)->start();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(std::string(s.error().message()).find("= 300 is outside [0, 255]"), std::string::npos)
      << s.error().message();
  // A well-known name vivid does not offer: zoom_absolute (a DIGIT's LED control).
  cfg.controls = parse_controls("led=3").value();
  auto led = make_v4l2_source(cfg);
  s = (*led)->start();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(std::string(s.error().message()).find("control 'led' (id 0x009a090d) is not offered"),
            std::string::npos)
      << s.error().message();
}

}  // namespace
}  // namespace tlvlink::capture
