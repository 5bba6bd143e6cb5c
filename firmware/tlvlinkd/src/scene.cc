#include "tlvlink/daemon/scene.h"

#include <dirent.h>

#include <algorithm>

#include "tlvlink/capture/device_select.h"
#include "tlvlink/capture/sensor_models.h"
#include "toml_reader.h"

namespace tlvlink::daemon {
namespace {

using internal::TableReader;

constexpr const char* kFingers[] = {"A", "B", "none"};
constexpr const char* kSources[] = {"v4l2", "libcamera"};
constexpr const char* kGrasp[] = {"detected", "commanded", "off"};

Status read_sensor(TableReader& r, SceneSensor& s) {
  TLV_TRY(r.text("name", s.name));
  TLV_ENSURE(!s.name.empty(), ErrorCode::kInvalidArgument, "%s: required (e.g. \"left\")",
             r.where("name").c_str());
  TLV_TRY(r.text("model", s.sensor_model));
  if (capture::find_sensor_model(s.sensor_model) == nullptr) {
    std::string known;
    for (const capture::SensorModel& k : capture::sensor_models())
      known += (known.empty() ? "" : ", ") + std::string(k.name);
    return Error::make(ErrorCode::kInvalidArgument, "%s: sensor model '%s' unknown (known: %s)",
                       r.where("model").c_str(), s.sensor_model.c_str(), known.c_str());
  }
  int32_t finger = 2, source = 0;
  TLV_TRY(r.choice("finger", {kFingers[0], kFingers[1], kFingers[2]}, finger));
  s.finger = kFingers[finger];
  TLV_TRY(r.choice("source", {kSources[0], kSources[1]}, source));
  s.source = kSources[source];
  TLV_TRY(r.text("device", s.device));
  TLV_ENSURE(!s.device.empty(), ErrorCode::kInvalidArgument,
             "%s: required (usb:VID:PID:SERIAL for v4l2, the camera id for libcamera)",
             r.where("device").c_str());
  if (source == 0) {
    auto sel = capture::parse_device_selector(s.device);
    if (!sel.ok()) return sel.error().with_context("%s", r.where("device").c_str());
  }
  return r.finish();
}

Status read_scene(TableReader& r, Scene& s) {
  TLV_TRY(r.text("description", s.description));
  TLV_TRY(r.texts("heads", s.heads));
  int32_t grasp = 2;
  TLV_TRY(r.choice("grasp", {kGrasp[0], kGrasp[1], kGrasp[2]}, grasp));
  s.grasp = kGrasp[grasp];
  if (r.has("output") && !r.is_array("output")) {
    std::string one;
    TLV_TRY(r.text("output", one));
    s.outputs = {one};
  } else {
    TLV_TRY(r.texts("output", s.outputs));
  }
  TLV_ENSURE(!s.outputs.empty(), ErrorCode::kInvalidArgument, "%s: at least one output",
             r.where("output").c_str());
  for (const std::string& o : s.outputs) {
    const bool ok = (o.rfind("jsonl:", 0) == 0 && o.size() > 6) || o.rfind("serial:", 0) == 0 ||
                    o.rfind("usb", 0) == 0;
    TLV_ENSURE(ok, ErrorCode::kInvalidArgument,
               "%s: '%s': expected jsonl:-, jsonl:FILE, serial:PATH or usb",
               r.where("output").c_str(), o.c_str());
  }
  TLV_TRY(r.flag("contact_gating", s.contact_gating));
  TLV_TRY(r.integer32("golden_pairs", s.golden_pairs, 1, 64));
  TLV_ASSIGN_OR_RETURN(const toml::array* sensors, r.array_of_tables("sensor"));
  TLV_ENSURE(sensors != nullptr && !sensors->empty(), ErrorCode::kInvalidArgument,
             "%s: at least one [[sensor]] is required", r.where("sensor").c_str());
  bool finger_a = false, finger_b = false;
  for (size_t i = 0; i < sensors->size(); ++i) {
    TableReader sub(*(*sensors)[i].as_table(), r.file(), r.child("sensor", static_cast<int>(i)));
    SceneSensor sensor;
    TLV_TRY(read_sensor(sub, sensor));
    finger_a = finger_a || sensor.finger == "A";
    finger_b = finger_b || sensor.finger == "B";
    s.sensors.push_back(std::move(sensor));
  }
  TLV_ENSURE(s.grasp == "off" || (finger_a && finger_b), ErrorCode::kInvalidArgument,
             "%s: grasp = \"%s\" needs two sensors, finger A and finger B",
             r.where("grasp").c_str(), s.grasp.c_str());
  return r.finish();
}

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

std::string list(const std::vector<std::string>& v) {
  std::string out = "[";
  for (size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + quoted(v[i]);
  return out + "]";
}

}  // namespace

SceneNeeds scene_needs(const Scene& scene) {
  SceneNeeds n;
  for (const std::string& o : scene.outputs) {
    n.stream = n.stream || o.rfind("jsonl:", 0) != 0;
    n.usb = n.usb || o.rfind("usb", 0) == 0;
  }
  for (const SceneSensor& s : scene.sensors) n.libcamera = n.libcamera || s.source == "libcamera";
  for (const std::string& h : scene.heads)
    n.zero_shot = n.zero_shot || h.rfind("zero-shot:", 0) == 0;
  return n;
}

Result<Scene> parse_scene(std::string_view text, const std::string& path) {
  toml::parse_result parsed = toml::parse(text, path);
  if (!parsed) {
    const toml::parse_error& e = parsed.error();
    return Error::make(ErrorCode::kInvalidArgument, "%s:%u:%u: %.*s", path.c_str(),
                       e.source().begin.line, e.source().begin.column,
                       static_cast<int>(e.description().size()), e.description().data());
  }
  Scene s;
  s.path = path;
  const size_t slash = path.find_last_of('/');
  s.name = path.substr(slash == std::string::npos ? 0 : slash + 1);
  if (s.name.size() > 5 && s.name.compare(s.name.size() - 5, 5, ".toml") == 0)
    s.name.resize(s.name.size() - 5);
  TableReader r(parsed.table(), path, "");
  TLV_TRY(read_scene(r, s));
  return s;
}

Result<Scene> load_scene(const std::string& path) {
  TLV_ASSIGN_OR_RETURN(const std::string text, internal::read_toml_file(path, "scene"));
  return parse_scene(text, path);
}

Result<Scene> find_scene(const std::string& scenes_dir, const std::string& name) {
  std::vector<std::string> known;
  if (DIR* d = ::opendir(scenes_dir.c_str())) {
    while (const dirent* e = ::readdir(d)) {
      const std::string f = e->d_name;
      if (f.size() > 5 && f.compare(f.size() - 5, 5, ".toml") == 0)
        known.push_back(f.substr(0, f.size() - 5));
    }
    ::closedir(d);
  }
  std::sort(known.begin(), known.end());
  if (std::find(known.begin(), known.end(), name) == known.end()) {
    std::string k;
    for (const std::string& n : known) k += (k.empty() ? "" : ", ") + n;
    return Error::make(ErrorCode::kInvalidArgument, "unknown scene '%s' (%s has: %s)", name.c_str(),
                       scenes_dir.c_str(), k.empty() ? "no scenes" : k.c_str());
  }
  return load_scene(scenes_dir + "/" + name + ".toml");
}

std::string scene_config_toml(const Scene& scene, const std::string& model_path, int32_t threads,
                              const std::string& origin) {
  std::string t;
  t += "# tlvlinkd configuration for scene '" + scene.name + "' (" + origin + ").\n";
  if (!scene.description.empty()) t += "# " + scene.description + "\n";
  t += "# Reference of every key: /usr/share/doc/tlvlink/tlvlinkd.toml. Set each sensor's USB\n"
       "# serial (`udevadm info /dev/video0 | grep SERIAL`), then: systemctl restart tlvlinkd\n\n";
  t += "model = " + quoted(model_path) + "\n";
  t += "threads = " + std::to_string(threads) + "\n";
  t += "verify_model = true\n";
  t += "heads = " + list(scene.heads) + "\n";
  t += "output = " + list(scene.outputs) + "\n\n";
  t += "[contact]\nenabled = " + std::string(scene.contact_gating ? "true" : "false") + "\n\n";
  t += "[grasp]\nmode = " + quoted(scene.grasp) + "\n";
  for (const SceneSensor& s : scene.sensors) {
    t += "\n[[sensor]]\nname = " + quoted(s.name) + "\nmodel = " + quoted(s.sensor_model) +
         "\nfinger = " + quoted(s.finger) + "\nsource = " + quoted(s.source) +
         "\ndevice = " + quoted(s.device) + "\n";
  }
  return t;
}

}  // namespace tlvlink::daemon
