#include "meta.h"

#include <sys/stat.h>

#include <string>

#include "tlvlink/touch/materials.h"

namespace tlvlink::datasets {
namespace {

OrderedJson material_json(const touch::MaterialSample& m) {
  return {{"class_id", m.class_id}, {"modulus_pa", m.modulus_pa},
          {"poisson", m.poisson},   {"friction", m.friction},
          {"sq_um", m.sq_um},       {"correlation_length_mm", m.correlation_length_mm},
          {"hurst", m.hurst},       {"hard", m.hard},
          {"rough", m.rough},       {"layer_mm", m.layer_mm}};
}

// An integer label exactly as written. get<int32_t>() converts whatever it is given: 1.5 reads
// as 1, true as 1 and 4294967299 wraps to 3, a valid class. `what` names the field in errors,
// which quote the value as written (2147483648, never -2147483648).
int32_t read_int(const Json& object, const char* key, const char* what, int64_t lo, int64_t hi,
                 const char* range) {
  const Json& v = object.at(key);
  if (!v.is_number_integer()) {
    throw Json::other_error::create(501, std::string(what) + " " + v.dump() + " is not an integer",
                                    &object);
  }
  const bool in_range = v.is_number_unsigned() ? v.get<uint64_t>() <= static_cast<uint64_t>(hi)
                                               : v.get<int64_t>() >= lo && v.get<int64_t>() <= hi;
  if (!in_range) {
    throw Json::other_error::create(501, std::string(what) + " " + v.dump() + " outside " + range,
                                    &object);
  }
  return static_cast<int32_t>(v.get<int64_t>());
}

// A class id is checked where it is read: an out-of-range one would otherwise index the class
// table later (exit 2 naming nothing) or read as "unlabelled" (-5) and be scored silently.
int32_t read_class_id(const Json& material) {
  const std::string range =
      "0.." + std::to_string(touch::kMaterialClassCount - 1) + " (or -1, unlabelled)";
  const int32_t id = read_int(material, "class_id", "material class_id", -1,
                              touch::kMaterialClassCount - 1, range.c_str());
  return id;
}

void read_material(const Json& j, touch::MaterialSample& m) {
  m.class_id = read_class_id(j);
  m.modulus_pa = j.at("modulus_pa").get<double>();
  m.poisson = j.at("poisson").get<double>();
  m.friction = j.at("friction").get<double>();
  m.sq_um = j.at("sq_um").get<double>();
  m.correlation_length_mm = j.at("correlation_length_mm").get<double>();
  m.hurst = j.at("hurst").get<double>();
  m.hard = j.at("hard").get<bool>();
  m.rough = read_int(j, "rough", "material rough", -1, 1, "-1..1 (1 rough, 0 smooth, -1 neither)");
  m.layer_mm = j.value("layer_mm", 0.0);  // recorded since issue 16; 0 = bulk or not recorded
}

OrderedJson contact_json(const touch::ContactState& c) {
  return {{"in_contact", c.in_contact},
          {"force_n", c.force_n},
          {"press_mm", c.press_mm},
          {"max_gel_indentation_mm", c.max_gel_indentation_mm},
          {"kappa", c.kappa},
          {"texture_kappa", c.texture_kappa},
          {"contact_area_mm2", c.contact_area_mm2},
          {"contact_radius_mm", c.contact_radius_mm},
          {"stick_radius_mm", c.stick_radius_mm},
          {"slip_ratio", c.slip_ratio},
          {"gross_slip", c.gross_slip},
          {"markers_deviating", c.markers_deviating},
          {"mean_shear_mm", c.mean_shear_mm}};
}

void read_contact(const Json& j, touch::ContactState& c) {
  c.in_contact = j.at("in_contact").get<bool>();
  c.force_n = j.at("force_n").get<double>();
  c.press_mm = j.at("press_mm").get<double>();
  c.max_gel_indentation_mm = j.at("max_gel_indentation_mm").get<double>();
  c.kappa = j.at("kappa").get<double>();
  c.texture_kappa = j.value("texture_kappa", 0.0);  // 0: written before it was recorded
  c.contact_area_mm2 = j.at("contact_area_mm2").get<double>();
  c.contact_radius_mm = j.at("contact_radius_mm").get<double>();
  c.stick_radius_mm = j.at("stick_radius_mm").get<double>();
  c.slip_ratio = j.at("slip_ratio").get<double>();
  c.gross_slip = j.at("gross_slip").get<bool>();
  c.markers_deviating = j.at("markers_deviating").get<int32_t>();
  c.mean_shear_mm = j.at("mean_shear_mm").get<double>();
}

OrderedJson variables_json(const GraspVariables& v) {
  return {{"grip_force_n", v.grip_force_n},
          {"friction", v.friction},
          {"contact_area_mm2", {v.contact_area_mm2[0], v.contact_area_mm2[1]}},
          {"finger_in_contact", {v.finger_in_contact[0], v.finger_in_contact[1]}},
          {"mass_kg", v.mass_kg},
          {"com_offset_mm", v.com_offset_mm},
          {"lift_accel_mps2", v.lift_accel_mps2},
          {"slip_ratio", v.slip_ratio},
          {"margin", v.margin}};
}

void read_variables(const Json& j, GraspVariables& v) {
  v.grip_force_n = j.at("grip_force_n").get<double>();
  v.friction = j.at("friction").get<double>();
  for (int f = 0; f < heads::kFingers; ++f) {
    v.contact_area_mm2[f] = j.at("contact_area_mm2").at(static_cast<size_t>(f)).get<double>();
    v.finger_in_contact[f] = j.at("finger_in_contact").at(static_cast<size_t>(f)).get<bool>();
  }
  v.mass_kg = j.at("mass_kg").get<double>();
  v.com_offset_mm = j.at("com_offset_mm").get<double>();
  v.lift_accel_mps2 = j.at("lift_accel_mps2").get<double>();
  v.slip_ratio = j.at("slip_ratio").get<double>();
  v.margin = j.at("margin").get<double>();
}

// "sensor_instance": an integer (touch) or one per finger (grasp). Sets written before the field
// existed were drawn on one sensor, instance 0. Throws like .at() on a malformed value.
int32_t read_instance(const Json& meta, int finger) {
  const auto it = meta.find("sensor_instance");
  if (it == meta.end()) return 0;
  const int32_t k = (it->is_array() ? it->at(static_cast<size_t>(finger)) : *it).get<int32_t>();
  if (k < 0) throw Json::other_error::create(501, "sensor_instance < 0", &meta);
  return k;
}

}  // namespace

bool parse_json(const std::string& text, Json& out, std::string& why) {
  try {
    out = Json::parse(text);
    return true;
  } catch (const Json::exception& e) {
    why = e.what();
    return false;
  }
}

OrderedJson touch_meta(const TouchSample& s, const std::string& key, bool test) {
  return {{"key", key},
          {"split", test ? "test" : "train"},
          {"session", s.session},
          {"frame_index", s.frame_index},
          {"object_id", s.object_id},
          {"sensor_instance", s.sensor_instance},
          {"sensor", s.sensor},
          {"material", material_json(s.material)},
          {"contact", contact_json(s.contact)}};
}

OrderedJson grasp_meta(const GraspEpisode& e, const std::string& key, bool test) {
  OrderedJson states = OrderedJson::array();
  for (int f = 0; f < heads::kFingers; ++f) {
    OrderedJson finger = OrderedJson::array();
    for (int m = 0; m < heads::kMoments; ++m) finger.push_back(contact_json(e.states[f][m]));
    states.push_back(std::move(finger));
  }
  return {{"key", key},
          {"split", test ? "test" : "train"},
          {"object_name", e.object_name},
          {"object_id", e.object_id},
          {"sensor_instance", {e.sensor_instance[0], e.sensor_instance[1]}},
          {"sensor", e.sensor},
          {"is_gripping", e.is_gripping},
          {"live_path", e.live_path},
          {"material", material_json(e.material)},
          {"variables", variables_json(e.variables)},
          {"states", std::move(states)}};
}

bool apply_touch_meta(const Json& meta, TouchSample& out, std::string& why) {
  try {
    out.object_id = meta.at("object_id").get<int32_t>();
    out.sensor_instance = read_instance(meta, 0);
    out.sensor = meta.value("sensor", std::string());  // recorded since issue 16
    read_material(meta.at("material"), out.material);
    read_contact(meta.at("contact"), out.contact);
    return true;
  } catch (const Json::exception& e) {
    why = e.what();
    return false;
  }
}

bool apply_grasp_meta(const Json& meta, GraspEpisode& out, std::string& why) {
  try {
    out.object_id = meta.at("object_id").get<int32_t>();
    for (int f = 0; f < heads::kFingers; ++f) out.sensor_instance[f] = read_instance(meta, f);
    out.sensor = meta.value("sensor", std::string());  // recorded since mixed-profile sets
    out.live_path = meta.value("live_path", false);    // recorded since live-path shares
    read_material(meta.at("material"), out.material);
    read_variables(meta.at("variables"), out.variables);
    const Json& states = meta.at("states");
    for (int f = 0; f < heads::kFingers; ++f)
      for (int m = 0; m < heads::kMoments; ++m)
        read_contact(states.at(static_cast<size_t>(f)).at(static_cast<size_t>(m)),
                     out.states[f][m]);
    return true;
  } catch (const Json::exception& e) {
    why = e.what();
    return false;
  }
}

void SidecarReader::open(const std::string& path) {
  struct stat st {};
  active_ = ::stat(path.c_str(), &st) == 0 && reader_.open(path).ok();
}

const Json* SidecarReader::next(const std::string& key, LoadReport& report) {
  if (!active_) return nullptr;
  std::string line;
  do {
    if (!reader_.next(line)) {
      stop("ends before the index does", report);
      return nullptr;
    }
  } while (is_blank(line));
  if (reader_.too_long()) {
    stop("line longer than " + std::to_string(kMaxLineBytes) + " bytes", report);
    return nullptr;
  }
  std::string why;
  if (!parse_json(line, current_, why)) {
    stop(why, report);
    return nullptr;
  }
  const auto it = current_.find("key");
  if (it == current_.end() || !it->is_string() || it->get<std::string>() != key) {
    stop("key does not match the index entry '" + key + "'", report);
    return nullptr;
  }
  return &current_;
}

void SidecarReader::skip() {
  if (!active_) return;
  std::string line;
  while (reader_.next(line) && is_blank(line)) {
  }
}

void SidecarReader::stop(const std::string& why, LoadReport& report) {
  active_ = false;
  report.add({ProblemKind::kSidecarMismatch, reader_.path(), reader_.line_number(),
              why + "; simulator metadata ignored from here on"});
}

}  // namespace tlvlink::datasets
