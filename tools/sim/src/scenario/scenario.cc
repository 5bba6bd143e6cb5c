// write_scenario: the timeline of scripted events rendered as both fingers' raw camera streams,
// with the ground truth of every frame and event.
#include "tlvlink/sim/scenario.h"

#include <sys/stat.h>

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>

#include <cstdio>
#include <map>
#include <memory>
#include <utility>

#include "tlvlink/capture/recording.h"
#include "tlvlink/capture/sensor_models.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/sim/generate.h"
#include "tlvlink/sim/materials.h"
#include "tlvlink/sim/raw_camera.h"

namespace tlvlink::sim {
namespace {

constexpr int32_t kA = 0, kB = 1;
constexpr const char* kFingerNames[kFingers] = {"A", "B"};

// Lengths of the scripted stretches, in seconds (a Feel-like grasp: close, hold, lift, release).
constexpr double kLeadIn = 2.0, kIdle = 1.0, kClose = 0.24, kHold = 1.2, kLift = 0.2, kAfter = 0.8,
                 kRelease = 0.24, kPressRamp = 0.4, kPressHold = 0.8;

uint64_t mix(uint64_t h, uint64_t v) {
  h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
  h *= 0xBF58476D1CE4E5B9ull;
  return h ^ (h >> 31);
}

// One frame of one finger: the scene, and a key when the frame may repeat an earlier one
// (static stretches; 0 = render it).
struct Shot {
  ContactScene scene;
  uint64_t static_key = 0;
  int32_t event = -1;
};

ContactScene scaled(ContactScene s, double t) {
  s.loading.force_n *= t;
  s.loading.shear_x_n *= t;
  s.loading.shear_y_n *= t;
  s.loading.torque_nmm *= t;
  return s;
}

ContactScene between(const ContactScene& a, const ContactScene& b, double t) {
  ContactScene s = a;
  const auto lerp = [t](double x, double y) { return x + (y - x) * t; };
  s.loading.shear_x_n = lerp(a.loading.shear_x_n, b.loading.shear_x_n);
  s.loading.shear_y_n = lerp(a.loading.shear_y_n, b.loading.shear_y_n);
  s.loading.torque_nmm = lerp(a.loading.torque_nmm, b.loading.torque_nmm);
  s.loading.slip_mm = b.loading.slip_mm * t;
  return s;
}

bool open_gel(const ContactScene& s) { return s.geometry.shape == Shape::kNone; }

struct Event {
  const char* kind = "grasp";
  int64_t start = 0, closed = -1, lifting = -1, end = 0;  // frame indices
  GraspEpisode episode;                                   // labels (frames unused)
};

class Timeline {
 public:
  Timeline(double fps, int32_t variants) : fps_(fps), variants_(variants) {}

  int64_t frames(double seconds) const {
    return std::max<int64_t>(1, std::llround(seconds * fps_));
  }
  int64_t size() const { return static_cast<int64_t>(shots_[kA].size()); }

  // A static stretch: `scene` on finger f, cycling through `variants_` rendered frames.
  void hold(int32_t f, const ContactScene& scene, int64_t n, uint64_t key, int32_t event) {
    for (int64_t k = 0; k < n; ++k)
      shots_[f].push_back({scene, mix(key, static_cast<uint64_t>(k % variants_)) | 1, event});
  }
  // A ramp: scene(t) for t in (0, 1], every frame rendered.
  template <typename SceneAt>
  void ramp(int32_t f, int64_t n, SceneAt scene_at, int32_t event) {
    for (int64_t k = 0; k < n; ++k)
      shots_[f].push_back(
          {scene_at(static_cast<double>(k + 1) / static_cast<double>(n)), 0, event});
  }
  const std::vector<Shot>& shots(int32_t f) const { return shots_[f]; }

 private:
  double fps_;
  int32_t variants_;
  std::vector<Shot> shots_[kFingers];
};

const char* hard_label_name(const MaterialSample& m) { return m.hard ? "hard" : "soft"; }
const char* rough_label_name(const MaterialSample& m) {
  return m.rough == 1 ? "\"rough\"" : m.rough == 0 ? "\"smooth\"" : "null";
}

// The frame's means over a 32x24 grid of blocks, per channel (the contact gate's reduction).
void block_means(const Frame& frame, std::vector<float>& out) {
  constexpr int32_t kGw = 32, kGh = 24;
  out.assign(static_cast<size_t>(kGw * kGh * 3), 0.0f);
  std::vector<int32_t> counts(static_cast<size_t>(kGw * kGh), 0);
  for (int32_t y = 0; y < frame.height; ++y) {
    const int32_t by = y * kGh / frame.height;
    for (int32_t x = 0; x < frame.width; ++x) {
      const auto b = static_cast<size_t>(by * kGw + x * kGw / frame.width);
      const uint8_t* p = &frame.rgb[(static_cast<size_t>(y) * static_cast<size_t>(frame.width) +
                                     static_cast<size_t>(x)) *
                                    3];
      for (size_t c = 0; c < 3; ++c) out[b * 3 + c] += p[c];
      ++counts[b];
    }
  }
  for (size_t b = 0; b < counts.size(); ++b)
    for (size_t c = 0; c < 3; ++c) out[b * 3 + c] /= static_cast<float>(std::max(counts[b], 1));
}

double max_difference(const std::vector<float>& a, const std::vector<float>& b) {
  float m = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

// Files written under temporary names, renamed when everything is written.
struct Staged {
  std::string final_path, temp_path;
};

}  // namespace

Result<ScenarioReport> write_scenario(const ScenarioOptions& o, const std::string& dir,
                                      const std::function<void(int64_t, int64_t)>& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  TLV_ENSURE(o.grasps >= 0 && o.grasps <= 1000 && o.presses >= 0 && o.presses <= 1000 &&
                 o.grasps + o.presses >= 1,
             ErrorCode::kInvalidArgument,
             "scenario: grasps = %d and presses = %d must be 0..1000 and not both 0", o.grasps,
             o.presses);
  TLV_ENSURE(o.static_variants >= 1 && o.static_variants <= 100, ErrorCode::kInvalidArgument,
             "scenario: static_variants = %d is outside 1..100", o.static_variants);
  TLV_ENSURE(o.dataset_jpeg_quality >= 1 && o.dataset_jpeg_quality <= 100,
             ErrorCode::kInvalidArgument, "scenario: dataset JPEG quality %d outside 1..100",
             o.dataset_jpeg_quality);
  TLV_ASSIGN_OR_RETURN(const SensorProfile profile, sensor_profile(o.sensor));
  const capture::SensorModel* model = capture::find_sensor_model(profile.name);
  TLV_ENSURE(model != nullptr, ErrorCode::kInvalidArgument,
             "scenario: sensor '%.*s' has no camera model (its format and frame rate)",
             static_cast<int>(profile.name.size()), profile.name.data());
  RawOptions raw_options;
  raw_options.jpeg_quality = o.jpeg_quality;
  // Two physical sensors, the same all session long.
  std::unique_ptr<RawCamera> cameras[kFingers];
  for (int32_t f = 0; f < kFingers; ++f) {
    TLV_ASSIGN_OR_RETURN(
        cameras[f], RawCamera::create(profile, sensor_instance_seed(o.seed, f + 1), raw_options));
    const RawLayout& l = cameras[f]->layout();
    TLV_ENSURE(l.width == model->width && l.height == model->height, ErrorCode::kInvalidArgument,
               "scenario: the simulated '%s' camera renders %dx%d, the camera model streams %dx%d",
               model->name.data(), l.width, l.height, model->width, model->height);
  }

  // Events: grasps and presses interleaved, objects from one grasp set.
  GraspSetOptions go;
  go.sensor = o.sensor;
  go.objects = o.grasps + o.presses;
  go.grasps_per_object = 1;
  go.vision_height = 8;
  go.vision_width = 8;
  go.seed = o.seed;
  TLV_ASSIGN_OR_RETURN(auto generator, GraspEpisodeGenerator::create(go));
  Timeline tl(model->fps, o.static_variants);
  std::vector<Event> events;
  ContactScene open;
  open.geometry.shape = Shape::kNone;
  const uint64_t idle_key = mix(o.seed, 1);
  for (int32_t f = 0; f < kFingers; ++f) tl.hold(f, open, tl.frames(kLeadIn), idle_key, -1);
  for (int32_t e = 0; e < o.grasps + o.presses; ++e) {
    // Spread the presses between the grasps.
    const int32_t events_total = o.grasps + o.presses;
    const bool press = (e + 1) * o.presses / events_total > e * o.presses / events_total;
    Event ev;
    GraspScenes sc;
    TLV_TRY(generator->generate(e, ev.episode, sc));
    for (int32_t f = 0; f < kFingers; ++f) tl.hold(f, open, tl.frames(kIdle), idle_key, -1);
    ev.start = tl.size();
    const uint64_t key = mix(o.seed, 100 + static_cast<uint64_t>(e));
    if (press) {
      ev.kind = "press";
      const ContactScene& s = sc.during[kA];
      const int64_t n = tl.frames(kPressRamp), h = tl.frames(kPressHold);
      tl.ramp(
          kA, n, [&](double t) { return scaled(s, t); }, e);
      tl.hold(kA, s, h, mix(key, 1), e);
      tl.ramp(
          kA, n, [&](double t) { return scaled(s, 1 - t + 1e-9); }, e);
      tl.hold(kB, open, 2 * n + h, idle_key, -1);
    } else {
      const int64_t close = tl.frames(kClose), hold = tl.frames(kHold), lift = tl.frames(kLift),
                    after = tl.frames(kAfter), release = tl.frames(kRelease);
      ev.closed = ev.start + close;
      ev.lifting = ev.closed + hold;
      for (int32_t f = 0; f < kFingers; ++f) {
        const ContactScene& d = sc.during[f];
        const ContactScene& a = sc.after[f];
        const uint64_t fk = mix(key, 10 + static_cast<uint64_t>(f));
        tl.ramp(
            f, close, [&](double t) { return open_gel(d) ? open : scaled(d, t); }, e);
        tl.hold(f, open_gel(d) ? open : d, hold, open_gel(d) ? idle_key : mix(fk, 2), e);
        if (open_gel(d)) {
          tl.hold(f, open, lift + after + release, idle_key, e);
        } else if (open_gel(a)) {  // the object is gone: the imprint fades as it drops
          tl.ramp(
              f, lift, [&](double t) { return scaled(d, 1 - t + 1e-9); }, e);
          tl.hold(f, open, after + release, idle_key, e);
        } else {
          tl.ramp(
              f, lift, [&](double t) { return between(d, a, t); }, e);
          tl.hold(f, a, after, mix(fk, 3), e);
          tl.ramp(
              f, release, [&](double t) { return scaled(a, 1 - t + 1e-9); }, e);
        }
      }
    }
    ev.end = tl.size();
    events.push_back(std::move(ev));
  }
  for (int32_t f = 0; f < kFingers; ++f) tl.hold(f, open, tl.frames(kIdle), idle_key, -1);

  // Render and record.
  ::mkdir(dir.c_str(), 0755);
  struct stat st {};
  TLV_ENSURE(::stat(dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode), ErrorCode::kIo,
             "scenario: cannot create the directory %s", dir.c_str());
  std::vector<Staged> files = {{dir + "/A.tlvraw", dir + "/.A.tlvraw.partial"},
                               {dir + "/B.tlvraw", dir + "/.B.tlvraw.partial"},
                               {dir + "/truth.jsonl", dir + "/.truth.jsonl.partial"},
                               {dir + "/commands.txt", dir + "/.commands.txt.partial"}};
  if (o.offline) {  // files[4..5]: the processed frames exactly; [6..7]: as datasets store them
    files.push_back({dir + "/A.offline.tlvraw", dir + "/.A.offline.tlvraw.partial"});
    files.push_back({dir + "/B.offline.tlvraw", dir + "/.B.offline.tlvraw.partial"});
    files.push_back({dir + "/A.dataset.tlvraw", dir + "/.A.dataset.tlvraw.partial"});
    files.push_back({dir + "/B.dataset.tlvraw", dir + "/.B.dataset.tlvraw.partial"});
  }
  for (const Staged& f : files) {
    struct stat existing {};
    TLV_ENSURE(o.overwrite || ::lstat(f.final_path.c_str(), &existing) != 0,
               ErrorCode::kInvalidArgument, "scenario: %s exists (--overwrite replaces it)",
               f.final_path.c_str());
  }
  capture::RecordingFormat format;
  format.format = {model->format, model->width, model->height,
                   model->format == image::PixelFormat::kYuyv ? model->width * 2 : 0};
  format.fps_numerator = static_cast<uint32_t>(std::lround(model->fps));
  const int64_t period = static_cast<int64_t>(std::llround(1e9 / model->fps));
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> truth(std::fopen(files[2].temp_path.c_str(), "w"),
                                                        &std::fclose);
  TLV_ENSURE(truth != nullptr, ErrorCode::kIo, "scenario: cannot write %s",
             files[2].temp_path.c_str());
  std::fprintf(
      truth.get(),
      "{\"type\":\"scenario\",\"sensor\":\"%s\",\"fps\":%g,\"seed\":%llu,\"grasps\":%d,"
      "\"presses\":%d,\"frames\":%lld,\"fingers\":[\"A\",\"B\"],\"finger_b_phase_ms\":%g}\n",
      model->name.data(), model->fps, static_cast<unsigned long long>(o.seed), o.grasps, o.presses,
      static_cast<long long>(tl.size()), static_cast<double>(o.finger_b_phase_ns) * 1e-6);
  ScenarioReport report;
  for (size_t e = 0; e < events.size(); ++e) {
    const Event& ev = events[e];
    const MaterialSample& m = ev.episode.material;
    const auto ms = [&](int64_t frame) {
      return frame < 0 ? -1.0 : static_cast<double>(frame * period) * 1e-6;
    };
    const bool grasp = std::string_view(ev.kind) == "grasp";
    report.grasps_succeeding += grasp && ev.episode.is_gripping ? 1 : 0;
    std::fprintf(
        truth.get(),
        "{\"type\":\"event\",\"id\":%zu,\"kind\":\"%s\",\"start_ms\":%.1f,\"closed_ms\":%.1f,"
        "\"lifting_ms\":%.1f,\"end_ms\":%.1f,\"first_seq\":%lld,\"last_seq\":%lld,"
        "\"success\":%s,\"material\":\"%s\",\"hard_soft\":\"%s\",\"rough_smooth\":%s,"
        "\"object\":\"%s\"}\n",
        e, ev.kind, ms(ev.start), ms(ev.closed), ms(ev.lifting), ms(ev.end),
        static_cast<long long>(ev.start), static_cast<long long>(ev.end - 1),
        grasp ? (ev.episode.is_gripping ? "true" : "false") : "null",
        material_classes()[static_cast<size_t>(m.class_id)].name.data(), hard_label_name(m),
        rough_label_name(m), ev.episode.object_name.c_str());
  }
  // The controller's marks, as a robot would log them: tlvlinkd's command_script.
  {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> commands(
        std::fopen(files[3].temp_path.c_str(), "w"), &std::fclose);
    TLV_ENSURE(commands != nullptr, ErrorCode::kIo, "scenario: cannot write %s",
               files[3].temp_path.c_str());
    std::fprintf(commands.get(),
                 "# The gripper controller's marks (tlvlinkd command_script): FINGER SEQUENCE "
                 "COMMAND\n");
    for (const Event& ev : events) {
      if (std::string_view(ev.kind) != "grasp") continue;
      std::fprintf(commands.get(), "A %lld closed\nA %lld lifting\n",
                   static_cast<long long>(ev.closed), static_cast<long long>(ev.lifting));
    }
    TLV_ENSURE(std::fflush(commands.get()) == 0 && !std::ferror(commands.get()) &&
                   ::fsync(::fileno(commands.get())) == 0,
               ErrorCode::kIo, "scenario: writing %s failed", files[3].temp_path.c_str());
  }
  std::vector<capture::RecordingWriter> writers, offline, dataset;
  capture::RecordingFormat offline_format = format, dataset_format = format;
  offline_format.format = {image::PixelFormat::kRgb24, model->view.width, model->view.height,
                           model->view.width * 3};
  dataset_format.format = {image::PixelFormat::kMjpeg, model->view.width, model->view.height, 0};
  for (int32_t f = 0; f < kFingers; ++f) {
    capture::WriterOptions wo;
    wo.origin_ns = 0;  // shared: B's phase survives
    wo.overwrite = true;
    TLV_ASSIGN_OR_RETURN(auto w, capture::RecordingWriter::create(
                                     files[static_cast<size_t>(f)].temp_path, format, wo));
    writers.push_back(std::move(w));
    if (o.offline) {
      TLV_ASSIGN_OR_RETURN(
          auto ow, capture::RecordingWriter::create(files[4 + static_cast<size_t>(f)].temp_path,
                                                    offline_format, wo));
      offline.push_back(std::move(ow));
      TLV_ASSIGN_OR_RETURN(
          auto dw, capture::RecordingWriter::create(files[6 + static_cast<size_t>(f)].temp_path,
                                                    dataset_format, wo));
      dataset.push_back(std::move(dw));
    }
  }
  struct Stored {
    capture::RecordedBytes bytes, offline, dataset;
    ContactState state;
    double signal_dn = 0;
  };
  std::map<uint64_t, Stored> stored[kFingers];
  // What the optics show of each frame: the largest 32x24 block-mean difference from the
  // finger's first (open-gel) frame, in DN. A contact the optics cannot show (a smooth flat
  // face filling the gel leaves every surface normal as it was) stays at the noise's ~1 DN.
  std::vector<float> open_blocks[kFingers], blocks;
  RawFrame raw;
  RenderOptions render_options;
  render_options.markers = o.markers;
  const int64_t total = tl.size();
  for (int64_t k = 0; k < total; ++k) {
    for (int32_t f = 0; f < kFingers; ++f) {
      const Shot& shot = tl.shots(f)[static_cast<size_t>(k)];
      const int64_t t = k * period + (f == kB ? o.finger_b_phase_ns : 0);
      const auto seq = static_cast<uint32_t>(k);
      ContactState state;
      double signal_dn = 0;
      auto hit = shot.static_key != 0 ? stored[f].find(shot.static_key) : stored[f].end();
      if (hit != stored[f].end()) {
        TLV_TRY(writers[static_cast<size_t>(f)].append_repeat(hit->second.bytes, t, seq));
        if (o.offline) {
          TLV_TRY(offline[static_cast<size_t>(f)].append_repeat(hit->second.offline, t, seq));
          TLV_TRY(dataset[static_cast<size_t>(f)].append_repeat(hit->second.dataset, t, seq));
        }
        state = hit->second.state;
        signal_dn = hit->second.signal_dn;
      } else {
        const uint64_t noise =
            mix(mix(o.seed, 7 + static_cast<uint64_t>(f)),
                shot.static_key != 0 ? shot.static_key : static_cast<uint64_t>(k) << 1);
        Status r = cameras[f]->render(shot.scene, render_options, noise, raw);
        if (!r.ok())
          return r.error().with_context("scenario frame %lld finger %s", static_cast<long long>(k),
                                        kFingerNames[f]);
        TLV_ASSIGN_OR_RETURN(const capture::RecordedBytes b,
                             writers[static_cast<size_t>(f)].append(raw.bytes, t, seq));
        capture::RecordedBytes ob, db;
        if (o.offline) {
          const image::Image processed{raw.processed.width, raw.processed.height, 3,
                                       raw.processed.rgb};
          TLV_ASSIGN_OR_RETURN(ob,
                               offline[static_cast<size_t>(f)].append(processed.pixels, t, seq));
          TLV_ASSIGN_OR_RETURN(const std::vector<uint8_t> jpeg,
                               image::encode_jpeg(processed, o.dataset_jpeg_quality));
          TLV_ASSIGN_OR_RETURN(db, dataset[static_cast<size_t>(f)].append(jpeg, t, seq));
        }
        state = raw.processed.state;
        block_means(raw.processed, blocks);
        if (open_blocks[f].empty()) open_blocks[f] = blocks;  // the lead-in: the open gel
        signal_dn = max_difference(blocks, open_blocks[f]);
        ++report.rendered;
        if (shot.static_key != 0) stored[f][shot.static_key] = {b, ob, db, state, signal_dn};
      }
      std::fprintf(truth.get(),
                   "{\"type\":\"frame\",\"finger\":\"%s\",\"seq\":%lld,\"offset_ms\":%.3f,"
                   "\"contact\":%s,\"force_n\":%.3f,\"area_mm2\":%.3f,\"signal_dn\":%.2f,"
                   "\"event\":%d}\n",
                   kFingerNames[f], static_cast<long long>(k), static_cast<double>(t) * 1e-6,
                   state.in_contact ? "true" : "false", state.force_n, state.contact_area_mm2,
                   signal_dn, shot.event);
    }
    if (progress) progress(k + 1, total);
  }
  for (auto* group : {&writers, &offline, &dataset}) {
    for (auto& w : *group) {
      report.file_bytes += static_cast<int64_t>(w.file_bytes());
      TLV_TRY(w.close());
    }
  }
  // Durable before the renames (the recordings sync themselves on close): a crash after the
  // renames must not leave a truth file shorter than its recordings.
  TLV_ENSURE(std::fflush(truth.get()) == 0 && !std::ferror(truth.get()) &&
                 ::fsync(::fileno(truth.get())) == 0,
             ErrorCode::kIo, "scenario: writing %s failed", files[2].temp_path.c_str());
  truth.reset();
  for (const Staged& s : files) {
    TLV_ENSURE(std::rename(s.temp_path.c_str(), s.final_path.c_str()) == 0, ErrorCode::kIo,
               "scenario: cannot rename %s to %s", s.temp_path.c_str(), s.final_path.c_str());
  }
  report.frames = total;
  report.seconds = static_cast<double>(total) / model->fps;
  report.render_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace tlvlink::sim
