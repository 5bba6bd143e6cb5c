// capture_probe: lists V4L2 capture nodes, or streams from one through the V4L2 source and
// prints what was negotiated, the frame rate from buffer timestamps and every counter. For
// bringing up a camera on a board; the README's runnable example (in the rig, against vivid).
//
//   capture_probe --list
//   capture_probe DEVICE FORMAT WxH [--fps F] [--frames N] [--warmup N] [--buffers N]
//                 [--controls "k=v, ..."] [--accept-other-size]
//   DEVICE: usb:VID:PID[:SERIAL] or a path; FORMAT: mjpeg, yuyv, nv12, rgb24, grey
// Exit status: 0 when N frames arrived, 1 on a capture error, 2 on bad arguments.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "tlvlink/capture/v4l2_source.h"

namespace {

using namespace tlvlink;
using namespace tlvlink::capture;

int usage() {
  std::fprintf(
      stderr,
      "usage: capture_probe --list\n"
      "       capture_probe DEVICE FORMAT WxH [--fps F] [--frames N] [--warmup N] [--buffers N]\n"
      "                     [--controls \"k=v, ...\"] [--accept-other-size]\n");
  return 2;
}

int list() {
  for (const DeviceInfo& d : list_v4l2_devices()) {
    std::printf("%-12s %04x:%04x serial '%s' port '%s' caps 0x%08x %s '%s'\n", d.path.c_str(),
                d.vendor_id, d.product_id, d.serial.c_str(), d.usb_port.c_str(), d.device_caps,
                d.can_capture() ? "capture" : "(no capture)", d.name.c_str());
  }
  return 0;
}

bool parse_format(const char* s, image::PixelFormat& f) {
  for (image::PixelFormat p :
       {image::PixelFormat::kMjpeg, image::PixelFormat::kYuyv, image::PixelFormat::kNv12,
        image::PixelFormat::kRgb24, image::PixelFormat::kGrey}) {
    if (std::strcmp(s, image::pixel_format_name(p)) == 0) {
      f = p;
      return true;
    }
  }
  return false;
}

void print_stats(const SourceStats& s) {
  std::printf(
      "delivered %llu, stale skipped %llu, dropped %llu, warm-up %llu, flagged %llu, empty %llu, "
      "short %llu, bad mjpeg %llu, timeouts %llu, stalls %llu, disconnects %llu, reconnects %llu; "
      "measured %.2f fps (nominal %.2f)%s\n",
      static_cast<unsigned long long>(s.delivered),
      static_cast<unsigned long long>(s.skipped_stale), static_cast<unsigned long long>(s.dropped),
      static_cast<unsigned long long>(s.warmup_discarded),
      static_cast<unsigned long long>(s.flagged_error), static_cast<unsigned long long>(s.empty),
      static_cast<unsigned long long>(s.short_frames), static_cast<unsigned long long>(s.bad_mjpeg),
      static_cast<unsigned long long>(s.timeouts), static_cast<unsigned long long>(s.stalls),
      static_cast<unsigned long long>(s.disconnects), static_cast<unsigned long long>(s.reconnects),
      s.measured_fps, s.nominal_fps, s.driver_timestamps ? "" : "; dequeue-time stamps");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::strcmp(argv[1], "--list") == 0) return list();
  if (argc < 4) return usage();
  V4l2Config c;
  c.label = "probe";
  auto sel = parse_device_selector(argv[1]);
  if (!sel.ok()) return std::fprintf(stderr, "%s\n", sel.error().message()), 2;
  c.device = std::move(sel).value();
  if (!parse_format(argv[2], c.format) || std::sscanf(argv[3], "%dx%d", &c.width, &c.height) != 2)
    return usage();
  int frames = 30;
  for (int i = 4; i < argc; ++i) {
    const std::string a = argv[i];
    const char* v = i + 1 < argc ? argv[i + 1] : nullptr;
    if (a == "--accept-other-size")
      c.accept_other_size = true;
    else if (a == "--fps" && v)
      c.fps = std::atof(argv[++i]);
    else if (a == "--frames" && v)
      frames = std::atoi(argv[++i]);
    else if (a == "--warmup" && v)
      c.warmup_frames = static_cast<uint32_t>(std::atoi(argv[++i]));
    else if (a == "--buffers" && v)
      c.buffers = static_cast<uint32_t>(std::atoi(argv[++i]));
    else if (a == "--controls" && v) {
      auto controls = parse_controls(argv[++i]);
      if (!controls.ok()) return std::fprintf(stderr, "%s\n", controls.error().message()), 2;
      c.controls = std::move(controls).value();
    } else {
      return usage();
    }
  }
  auto src = make_v4l2_source(c);
  if (!src.ok()) return std::fprintf(stderr, "%s\n", src.error().message()), 2;
  if (Status s = (*src)->start(); !s.ok()) {
    std::fprintf(stderr, "%s: %s\n", error_code_name(s.error().code()), s.error().message());
    return 1;
  }
  const image::FrameFormat& f = (*src)->format();
  std::printf("%s: %s %dx%d stride %d, %u buffers of %zu bytes, nominal %.2f fps\n", (*src)->name(),
              image::pixel_format_name(f.format), f.width, f.height, f.stride,
              (*src)->buffer_count(), (*src)->buffer_bytes(), (*src)->stats().nominal_fps);
  for (const AppliedControl& a : (*src)->applied_controls()) {
    std::printf("control %s (0x%08x) = %lld\n", a.key.c_str(), a.id,
                static_cast<long long>(a.value));
  }
  int got = 0, errors = 0;
  while (got < frames && errors < 20) {
    auto frame = (*src)->next(2000);
    if (!frame.ok()) {
      ++errors;
      std::printf("%s: %s\n", error_code_name(frame.error().code()), frame.error().message());
      continue;
    }
    ++got;
    if (got == 1 || got == frames) {
      std::printf("frame %llu: %zu bytes, t %lld ns, %u older skipped\n",
                  static_cast<unsigned long long>(frame->sequence), frame->bytes.size(),
                  static_cast<long long>(frame->timestamp_ns), frame->skipped_before);
    }
    (*src)->release();
  }
  print_stats((*src)->stats());
  return got == frames ? 0 : 1;
}
