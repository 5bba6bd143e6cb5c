#include "tlvlink/daemon/config.h"

#include "frame_images.h"
#include "tlvlink/capture/device_select.h"
#include "tlvlink/capture/frame_source.h"
#include "toml_reader.h"
#if defined(TLVLINK_HAVE_STREAM)
#include "tlvlink/transport/transport_spec.h"
#endif

namespace tlvlink::daemon {
namespace {

using internal::TableReader;

constexpr int64_t kMs = 1'000'000;
// A sensor's name goes into every JSON line and stream message: kept short so a record always
// fits the output's fixed line buffer.
constexpr size_t kMaxSensorName = 64;

Status read_contact(TableReader& r, pipeline::ProcessorOptions& p) {
  TLV_TRY(r.flag("enabled", p.contact_gating));
  pipeline::ContactGateOptions& c = p.contact;
  TLV_TRY(r.integer32("reference_frames", c.reference_frames, 1, 1000));
  TLV_TRY(r.integer32("grid_width", c.grid_width, 1, 256));
  TLV_TRY(r.integer32("grid_height", c.grid_height, 1, 256));
  TLV_TRY(r.number32("noise_multiple", c.noise_multiple, 0.1f, 1000));
  TLV_TRY(r.number32("min_threshold_dn", c.min_threshold_dn, 0, 255));
  TLV_TRY(r.number32("release_fraction", c.release_fraction, 0.01f, 1));
  TLV_TRY(r.integer32("release_frames", c.release_frames, 1, 1000));
  TLV_TRY(r.number32("drift_rate", c.drift_rate, 0, 0.99f));
  return r.finish();
}

Status read_grasp(TableReader& r, pipeline::ProcessorOptions& p) {
  int32_t mode = 0;
  TLV_TRY(r.choice("mode", {"detected", "commanded", "off"}, mode));
  p.grasp = mode != 2;
  p.grasp_options.mode = mode == 1 ? pipeline::GraspOptions::Mode::kCommanded
                                   : pipeline::GraspOptions::Mode::kDetected;
  pipeline::GraspOptions& g = p.grasp_options;
  const auto ms = [&](const char* key, int64_t& ns) -> Status {
    int64_t v = ns / kMs;
    TLV_TRY(r.integer(key, v, 0, 60'000));
    ns = v * kMs;
    return {};
  };
  TLV_TRY(ms("onset_window_ms", g.onset_window_ns));
  TLV_TRY(ms("settle_ms", g.settle_ns));
  TLV_TRY(ms("after_delay_ms", g.after_delay_ns));
  TLV_TRY(ms("idle_refresh_ms", g.idle_refresh_ns));
  TLV_TRY(ms("before_max_age_ms", g.before_max_age_ns));
  TLV_TRY(ms("pair_tolerance_ms", g.pair_tolerance_ns));
  TLV_TRY(ms("frame_timeout_ms", g.frame_timeout_ns));
  TLV_ENSURE(g.frame_timeout_ns > 0, ErrorCode::kInvalidArgument, "%s: must be > 0",
             r.where("frame_timeout_ms").c_str());
  return r.finish();
}

Status read_sensor(TableReader& r, SensorConfig& s) {
  TLV_TRY(r.text("name", s.name));
  TLV_ENSURE(!s.name.empty(), ErrorCode::kInvalidArgument, "%s: required (e.g. \"left\")",
             r.where("name").c_str());
  TLV_ENSURE(s.name.size() <= kMaxSensorName, ErrorCode::kInvalidArgument,
             "%s: %zu bytes; at most %zu", r.where("name").c_str(), s.name.size(), kMaxSensorName);
  TLV_TRY(r.text("model", s.sensor_model));
  const capture::SensorModel* m = capture::find_sensor_model(s.sensor_model);
  if (m == nullptr) {
    std::string known;
    for (const capture::SensorModel& k : capture::sensor_models())
      known += (known.empty() ? "" : ", ") + std::string(k.name);
    return Error::make(ErrorCode::kInvalidArgument, "%s: sensor model '%s' unknown (known: %s)",
                       r.where("model").c_str(), s.sensor_model.c_str(), known.c_str());
  }
  s.format = {m->format, m->width, m->height, 0};
  s.fps = m->fps;
  s.view = m->view;
  s.warmup_frames = m->warmup_frames;
  int32_t finger = 2;
  TLV_TRY(r.choice("finger", {"A", "B", "none"}, finger));
  s.finger = finger == 2 ? -1 : finger;
  int32_t source = 0;
  TLV_TRY(r.choice("source", {"v4l2", "libcamera", "replay"}, source));
  s.source = static_cast<SourceKind>(source);
#if !defined(TLVLINK_HAVE_LIBCAMERA)
  TLV_ENSURE(s.source != SourceKind::kLibcamera, ErrorCode::kInvalidArgument,
             "%s: this tlvlinkd was built without libcamera (TLVLINK_WITH_LIBCAMERA=OFF)",
             r.where("source").c_str());
#endif
  TLV_TRY(r.text("device", s.device));
  if ((s.source == SourceKind::kV4l2 || s.source == SourceKind::kReplay) && s.device.empty()) {
    return Error::make(ErrorCode::kInvalidArgument, "%s: required for source '%s' (%s)",
                       r.where("device").c_str(), source_kind_name(s.source),
                       s.source == SourceKind::kV4l2 ? "usb:VID:PID[:SERIAL] or a /dev path"
                                                     : "the recording to play");
  }
  if (s.source == SourceKind::kV4l2) {
    auto sel = capture::parse_device_selector(s.device);
    if (!sel.ok()) return sel.error().with_context("%s", r.where("device").c_str());
  }
  int32_t format = -1;
  TLV_TRY(r.choice("format", {"mjpeg", "yuyv", "nv12", "rgb24", "grey"}, format));
  if (format >= 0) s.format.format = static_cast<image::PixelFormat>(format);
  TLV_TRY(r.integer32("width", s.format.width, 1, 16384));
  TLV_TRY(r.integer32("height", s.format.height, 1, 16384));
  TLV_TRY(r.number("fps", s.fps, 0, 1000));
  int64_t buffers = s.buffers, warmup = s.warmup_frames;
  TLV_TRY(r.integer("buffers", buffers, capture::kMinBuffers, capture::kMaxBuffers));
  TLV_TRY(r.integer("warmup_frames", warmup, 0, capture::kMaxWarmupFrames));
  s.buffers = static_cast<uint32_t>(buffers);
  s.warmup_frames = static_cast<uint32_t>(warmup);
  TLV_TRY(r.integer32("watchdog_ms", s.watchdog_ms, 50, 60000));
  TLV_TRY(r.flag("accept_other_size", s.accept_other_size));
  TLV_TRY(r.flag("wait_for_device", s.wait_for_device));
  std::string controls;
  TLV_TRY(r.text("controls", controls));
  if (!controls.empty()) {
    auto parsed = capture::parse_controls(controls);
    if (!parsed.ok()) return parsed.error().with_context("%s", r.where("controls").c_str());
    s.controls = std::move(parsed).value();
  }
  double crop = s.view.crop;
  TLV_TRY(r.number("crop", crop, 0, 0.45));
  s.view.crop = crop;
  TLV_TRY(r.integer32("jpeg_scale", s.view.jpeg_scale_denominator, 0, 8));
  const int32_t d = s.view.jpeg_scale_denominator;
  TLV_ENSURE(d == 0 || d == 1 || d == 2 || d == 4 || d == 8, ErrorCode::kInvalidArgument,
             "%s: %d is not 0 (auto), 1, 2, 4 or 8", r.where("jpeg_scale").c_str(), d);
  // Frames already upright (a DIGIT's processed frames, recorded as they were saved) need no
  // turning; a sensor whose camera sends them turned says so in its model.
  int32_t orientation = -1;
  TLV_TRY(r.choice("orientation", {"upright", "transposed"}, orientation));
  if (orientation >= 0) s.view.orientation = static_cast<image::Orientation>(orientation);
  TLV_TRY(r.flag("realtime", s.realtime));
  TLV_TRY(r.flag("loop", s.loop));
  TLV_TRY(r.flag("verify", s.verify));
  return r.finish();
}

// After the sensors and the contact grid: whether each sensor's image fits a FrameImage.
Status read_frame_images(TableReader& r, DaemonConfig& c, int streams) {
  int32_t kind = 0;
  TLV_TRY(r.choice("frame_images", {"off", "view", "input"}, kind));
  c.frame_images = static_cast<FrameImageKind>(kind);
  TLV_TRY(r.integer32("frame_images_per_second", c.frame_images_per_second, 1, 15));
  TLV_TRY(r.integer32("frame_image_quality", c.frame_image_quality, 20, 95));
  TLV_TRY(r.integer32("frame_image_max_side", c.frame_image_max_side, 16, 1024));
  if (c.frame_images == FrameImageKind::kOff) return {};
  TLV_ENSURE(streams == 1, ErrorCode::kInvalidArgument,
             "%s: images go on the stream link: add an output serial:..., pty:... or usb",
             r.where("frame_images").c_str());
  const pipeline::ContactGateOptions& g = c.processing.contact;
  for (const SensorConfig& s : c.sensors) {
    // The view at its sent size; the model's input is checked at start, once its size is known.
    const internal::ImageSize size =
        internal::frame_image_size(s.view.width, s.view.height, c.frame_image_max_side);
    const int32_t gw = std::min(g.grid_width, s.view.width),
                  gh = std::min(g.grid_height, s.view.height);
    TLV_TRY(internal::check_frame_image_fits(size.width, size.height, c.frame_image_quality,
                                             gw <= 255 && gh <= 255 ? gw * gh : 0,
                                             r.where("frame_image_max_side").c_str()));
  }
  return {};
}

Status read_top(TableReader& r, DaemonConfig& c) {
  TLV_TRY(r.text("model", c.model));
  TLV_ENSURE(!c.model.empty(), ErrorCode::kInvalidArgument, "%s: required (the .tlvm to run)",
             r.where("model").c_str());
  int32_t executor = 0;
  TLV_TRY(r.choice("executor", {"xnnpack", "reference"}, executor));
  c.executor = executor == 0 ? "xnnpack" : "reference";
  TLV_TRY(r.integer32("threads", c.threads, 1, kMaxThreads));
  TLV_TRY(r.flag("verify_model", c.verify_model));
  TLV_TRY(r.text("model_public_key", c.model_public_key));
  if (r.has("output") && !r.is_array("output")) {
    std::string one;
    TLV_TRY(r.text("output", one));
    c.outputs = {one};
  } else {
    TLV_TRY(r.texts("output", c.outputs));
  }
  TLV_ENSURE(!c.outputs.empty(), ErrorCode::kInvalidArgument, "%s: at least one output",
             r.where("output").c_str());
  int streams = 0;
  for (const std::string& o : c.outputs) {
    const bool jsonl = o.rfind("jsonl:", 0) == 0 && o.size() > 6;
    const bool stream =
        o.rfind("serial:", 0) == 0 || o.rfind("pty:", 0) == 0 || o.rfind("usb", 0) == 0;
    TLV_ENSURE(jsonl || stream, ErrorCode::kInvalidArgument,
               "%s: '%s': expected jsonl:-, jsonl:FILE, serial:PATH, pty:LINK or usb",
               r.where("output").c_str(), o.c_str());
    streams += stream ? 1 : 0;
    // The link string checked as start checks it (options, baud, a pty link that is not ours).
#if defined(TLVLINK_HAVE_STREAM)
    if (stream) {
      auto link = transport::make_transport(o);
      if (!link.ok()) return link.error().with_context("%s", r.where("output").c_str());
    }
#else
    TLV_ENSURE(
        !stream, ErrorCode::kInvalidArgument,
        "%s: '%s': this tlvlinkd was built without the stream link (TLVLINK_WITH_SERIAL=OFF)",
        r.where("output").c_str(), o.c_str());
#endif
  }
  TLV_ENSURE(streams <= 1, ErrorCode::kInvalidArgument, "%s: at most one stream link (got %d)",
             r.where("output").c_str(), streams);
  int32_t control = 0;
  TLV_TRY(r.choice("control", {"none", "stdin"}, control));
  c.control = static_cast<ControlInput>(control);
  TLV_TRY(r.text("command_script", c.command_script));
  TLV_TRY(r.integer32("status_interval_ms", c.status_interval_ms, 100, 600'000));
  TLV_TRY(r.flag("status_line", c.status_line));
  TLV_TRY(r.integer32("queue_frames", c.queue_frames, 1, kMaxQueueFrames));
  TLV_TRY(r.integer32("output_queue", c.output_queue, 1, kMaxOutputQueue));
  TLV_TRY(r.integer("run_for_ms", c.run_for_ms, 0, INT64_MAX / kMs));
  TLV_TRY(r.integer("max_frames", c.max_frames, 0, INT64_MAX));
  TLV_TRY(r.texts("heads", c.processing.heads));
  TLV_ENSURE(c.processing.heads.size() <= static_cast<size_t>(pipeline::kMaxHeads),
             ErrorCode::kInvalidArgument, "%s: %zu heads; at most %d are reported per frame",
             r.where("heads").c_str(), c.processing.heads.size(), pipeline::kMaxHeads);
  int64_t smoothing_ms = c.processing.smoothing_tau_ns / kMs;
  TLV_TRY(r.integer("smoothing_ms", smoothing_ms, 0, 60'000));
  c.processing.smoothing_tau_ns = smoothing_ms * kMs;
  TLV_TRY(r.flag("embedding", c.processing.report_embedding));
  if (auto t = r.table("contact"); !t.ok()) {
    return t.error();
  } else if (*t != nullptr) {
    TableReader sub(**t, r.file(), "contact");
    TLV_TRY(read_contact(sub, c.processing));
  }
  if (auto t = r.table("grasp"); !t.ok()) {
    return t.error();
  } else if (*t != nullptr) {
    TableReader sub(**t, r.file(), "grasp");
    TLV_TRY(read_grasp(sub, c.processing));
  }
  TLV_ASSIGN_OR_RETURN(const toml::array* sensors, r.array_of_tables("sensor"));
  TLV_ENSURE(sensors != nullptr && !sensors->empty(), ErrorCode::kInvalidArgument,
             "%s: at least one [[sensor]] is required", r.where("sensor").c_str());
  TLV_ENSURE(sensors->size() <= static_cast<size_t>(pipeline::kMaxSensors),
             ErrorCode::kInvalidArgument, "%s: %zu sensors; at most %d", r.where("sensor").c_str(),
             sensors->size(), pipeline::kMaxSensors);
  for (size_t i = 0; i < sensors->size(); ++i) {
    TableReader sub(*(*sensors)[i].as_table(), r.file(), r.child("sensor", static_cast<int>(i)));
    SensorConfig s;
    TLV_TRY(read_sensor(sub, s));
    for (const SensorConfig& other : c.sensors) {
      TLV_ENSURE(other.name != s.name, ErrorCode::kInvalidArgument,
                 "%s: a second sensor named '%s'", sub.where("name").c_str(), s.name.c_str());
      TLV_ENSURE(s.source != SourceKind::kV4l2 || other.source != SourceKind::kV4l2 ||
                     other.device != s.device,
                 ErrorCode::kInvalidArgument,
                 "%s: sensors '%s' and '%s' both select %s; add each camera's USB serial "
                 "(usb:VID:PID:SERIAL)",
                 sub.where("device").c_str(), other.name.c_str(), s.name.c_str(), s.device.c_str());
      TLV_ENSURE(s.finger < 0 || other.finger != s.finger, ErrorCode::kInvalidArgument,
                 "%s: sensors '%s' and '%s' are both finger %c", sub.where("finger").c_str(),
                 other.name.c_str(), s.name.c_str(), s.finger == 0 ? 'A' : 'B');
    }
    c.sensors.push_back(std::move(s));
  }
  TLV_TRY(read_frame_images(r, c, streams));
  return r.finish();
}

}  // namespace

const char* source_kind_name(SourceKind k) {
  switch (k) {
    case SourceKind::kV4l2: return "v4l2";
    case SourceKind::kLibcamera: return "libcamera";
    case SourceKind::kReplay: return "replay";
  }
  return "?";
}

Result<DaemonConfig> parse_config(std::string_view text, const std::string& name) {
  toml::parse_result parsed = toml::parse(text, name);
  if (!parsed) {
    const toml::parse_error& e = parsed.error();
    return Error::make(ErrorCode::kInvalidArgument, "%s:%u:%u: %.*s", name.c_str(),
                       e.source().begin.line, e.source().begin.column,
                       static_cast<int>(e.description().size()), e.description().data());
  }
  DaemonConfig c;
  c.path = name;
  TableReader r(parsed.table(), name, "");
  TLV_TRY(read_top(r, c));
  return c;
}

Result<DaemonConfig> load_config(const std::string& path) {
  TLV_ASSIGN_OR_RETURN(const std::string text, internal::read_toml_file(path, "configuration"));
  TLV_ASSIGN_OR_RETURN(DaemonConfig c, parse_config(text, path));
  TLV_TRY(check_config_paths(c));
  return c;
}

}  // namespace tlvlink::daemon
