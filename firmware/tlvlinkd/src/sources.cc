#include "sources.h"

#include "tlvlink/capture/replay_source.h"
#include "tlvlink/capture/sensor_models.h"
#include "tlvlink/capture/v4l2_source.h"
#if defined(TLVLINK_HAVE_LIBCAMERA)
#include "tlvlink/capture/libcamera_source.h"
#endif

namespace tlvlink::daemon::internal {
namespace {

Result<std::unique_ptr<capture::FrameSource>> v4l2(const SensorConfig& s) {
  capture::V4l2Config c;
  c.label = s.name;
  TLV_ASSIGN_OR_RETURN(c.device, capture::parse_device_selector(s.device));
  c.format = s.format.format;
  c.width = s.format.width;
  c.height = s.format.height;
  c.fps = s.fps;
  c.accept_other_size = s.accept_other_size;
  c.buffers = s.buffers;
  c.warmup_frames = s.warmup_frames;
  c.watchdog_ms = s.watchdog_ms;
  c.wait_for_device = s.wait_for_device;
  c.controls = s.controls;
  TLV_ASSIGN_OR_RETURN(auto src, capture::make_v4l2_source(c));
  return std::unique_ptr<capture::FrameSource>(std::move(src));
}

Result<std::unique_ptr<capture::FrameSource>> libcamera(const SensorConfig& s) {
#if defined(TLVLINK_HAVE_LIBCAMERA)
  capture::LibcameraConfig c;
  c.label = s.name;
  c.camera_id = s.device;
  c.format = s.format.format;
  c.width = s.format.width;
  c.height = s.format.height;
  c.fps = s.fps;
  c.accept_other_size = s.accept_other_size;
  c.buffers = s.buffers;
  c.warmup_frames = s.warmup_frames;
  TLV_ASSIGN_OR_RETURN(auto src, capture::make_libcamera_source(c));
  return std::unique_ptr<capture::FrameSource>(std::move(src));
#else
  return Error::make(ErrorCode::kInvalidArgument,
                     "sensor '%s': this tlvlinkd was built without libcamera "
                     "(TLVLINK_WITH_LIBCAMERA=OFF)",
                     s.name.c_str());
#endif
}

Result<std::unique_ptr<capture::FrameSource>> replay(const SensorConfig& s) {
  capture::ReplayConfig c;
  c.label = s.name;
  c.path = s.device;
  c.realtime = s.realtime;
  c.loop = s.loop;
  c.verify = s.verify;
  c.warmup_frames = s.warmup_frames;
  return capture::make_replay_source(c);
}

// The recording must hold what the sensor's configuration says the camera streams: a replay is
// checked like a camera that ignored the requested format.
Status check_replay_format(const SensorConfig& s, const capture::FrameSource& src) {
  const image::FrameFormat& got = src.format();
  // The sensor models whose camera streams what the recording holds: the likely fix.
  std::string models;
  for (const capture::SensorModel& m : capture::sensor_models()) {
    if (m.format == got.format && m.width == got.width && m.height == got.height)
      models += (models.empty() ? "" : ", ") + std::string(m.name);
  }
  TLV_ENSURE(
      got.format == s.format.format &&
          ((got.width == s.format.width && got.height == s.format.height) || s.accept_other_size),
      ErrorCode::kCaptureFormatRefused,
      "sensor '%s': recording %s holds %s %dx%d, the sensor is configured for %s %dx%d%s%s%s",
      s.name.c_str(), s.device.c_str(), image::pixel_format_name(got.format), got.width, got.height,
      image::pixel_format_name(s.format.format), s.format.width, s.format.height,
      models.empty() ? "" : " (sensor models that stream it: ", models.c_str(),
      models.empty() ? "" : ")");
  return {};
}

}  // namespace

Result<std::vector<std::unique_ptr<capture::FrameSource>>> make_sources(
    const DaemonConfig& config) {
  std::vector<std::unique_ptr<capture::FrameSource>> out;
  for (const SensorConfig& s : config.sensors) {
    Result<std::unique_ptr<capture::FrameSource>> src = s.source == SourceKind::kV4l2 ? v4l2(s)
                                                        : s.source == SourceKind::kLibcamera
                                                            ? libcamera(s)
                                                            : replay(s);
    if (!src.ok()) return src.error();
    if (Status st = (*src)->start(); !st.ok()) {
      return st.error().with_context("sensor '%s'", s.name.c_str());
    }
    if (s.source == SourceKind::kReplay) TLV_TRY(check_replay_format(s, **src));
    out.push_back(std::move(src).value());
  }
  return out;
}

}  // namespace tlvlink::daemon::internal
