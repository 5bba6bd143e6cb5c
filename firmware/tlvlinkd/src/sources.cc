#include "sources.h"

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

}  // namespace

Result<std::vector<std::unique_ptr<capture::FrameSource>>> make_sources(const DaemonConfig& config) {
  std::vector<std::unique_ptr<capture::FrameSource>> out;
  for (const SensorConfig& s : config.sensors) {
    Result<std::unique_ptr<capture::FrameSource>> src =
        s.source == SourceKind::kV4l2        ? v4l2(s)
        : s.source == SourceKind::kLibcamera ? libcamera(s)
                                             : Error::make(ErrorCode::kInvalidArgument,
                                                           "sensor '%s': source '%s' is not built "
                                                           "into this tlvlinkd",
                                                           s.name.c_str(),
                                                           source_kind_name(s.source));
    if (!src.ok()) return src.error();
    if (Status st = (*src)->start(); !st.ok()) {
      return st.error().with_context("sensor '%s'", s.name.c_str());
    }
    out.push_back(std::move(src).value());
  }
  return out;
}

}  // namespace tlvlink::daemon::internal
