#include "predictions.h"

#include <map>

#include "truth.h"

namespace tlvlink::score::internal {
namespace {

int32_t finger_of(const std::string& sensor, const std::vector<std::string>& fingers) {
  return sensor == fingers[0] ? 0 : sensor == fingers[1] ? 1 : -1;
}

// What a Hello names: sensors, and heads with their labels, by index.
struct Names {
  std::map<int64_t, std::string> sensors;
  std::map<int64_t, std::pair<std::string, std::vector<std::string>>> heads;
};

void read_hello(const json& j, Names& n) {
  n = {};
  for (const json& s : j.value("sensors", json::array()))
    n.sensors[s.value("index", int64_t{-1})] = s.value("name", "");
  int64_t i = 0;
  for (const json& h : j.value("heads", json::array())) {
    n.heads[i++] = {h.value("name", ""),
                    h.value("labels", json::array()).get<std::vector<std::string>>()};
  }
}

// A head's name and top label: as the line gives them, else from the Hello (the first of equal
// maxima, as the writer picks it).
std::pair<std::string, std::string> head_label(const json& h, const Names& names) {
  std::string name = h.value("name", ""), label = h.value("top_label", "");
  const auto it = names.heads.find(h.value("head", int64_t{-1}));
  if (it == names.heads.end()) return {name, label};
  if (name.empty()) name = it->second.first;
  if (label.empty()) {
    const std::vector<double> p = h.value("probabilities", std::vector<double>{});
    size_t top = 0;
    for (size_t k = 1; k < p.size(); ++k) top = p[k] > p[top] ? k : top;
    if (top < p.size() && top < it->second.second.size()) label = it->second.second[top];
  }
  return {name, label};
}

// The one form (protocol 1.3 and later; a 1.2 board has no gate state: its contact flag).
FrameRecord frame_prediction(const json& j, const Names& names,
                             const std::vector<std::string>& fingers) {
  FrameRecord r;
  std::string sensor = j.value("sensor_name", "");
  if (sensor.empty()) {
    auto it = names.sensors.find(j.value("sensor", int64_t{-1}));
    if (it != names.sensors.end()) sensor = it->second;
  }
  r.finger = finger_of(sensor, fingers);
  r.seq = j.value("frame_sequence", int64_t{-1});
  const std::string gate = j.contains("gate") && j["gate"].is_string() ? j["gate"] : "unknown";
  r.gate = gate == "calibrating"                            ? Gate::kCalibrating
           : gate == "contact"                              ? Gate::kContact
           : gate == "unknown" && j.value("contact", false) ? Gate::kContact
                                                            : Gate::kNone;
  r.encoded = j.value("infer_end_ns", int64_t{0}) != 0;  // 0: the encoder did not run (spec §7)
  for (const json& h : j.value("heads", json::array())) {
    auto [name, label] = head_label(h, names);
    r.labels.emplace_back(std::move(name), lower(std::move(label)));
  }
  return r;
}

GraspRecord grasp_prediction(const json& j, const Names& names,
                             const std::vector<std::string>& fingers) {
  GraspRecord r;
  r.computed = j.value("status", "") == "computed";
  r.reason = j.value("reason_text", "");
  if (r.reason.empty() && j.contains("reason")) r.reason = j["reason"].dump();
  for (const json& f : j.value("frames", json::array())) {
    const int64_t sensor = f.value("sensor", int64_t{-1});
    auto it = names.sensors.find(sensor);
    // Without a Hello: sensor 0 is finger A, as the daemon numbers its fingers.
    const int32_t finger =
        it != names.sensors.end() ? finger_of(it->second, fingers) : static_cast<int32_t>(sensor);
    if (finger == 0 && f.value("phase", "") == "during")
      r.during_seq_a = f.value("frame_sequence", int64_t{-1});
  }
  const json& p = j.contains("probability") ? j["probability"] : json();
  r.success = p.is_number() && p.get<double>() >= 0.5;
  return r;
}

// tlvlinkd before protocol 1.3.
FrameRecord old_frame(const json& j, const std::vector<std::string>& fingers) {
  FrameRecord r;
  r.finger = finger_of(j.value("sensor", ""), fingers);
  r.seq = j.value("seq", int64_t{-1});
  const std::string gate = j.value("contact", "none");
  r.gate = gate == "calibrating" ? Gate::kCalibrating
           : gate == "contact"   ? Gate::kContact
                                 : Gate::kNone;
  r.encoded = j.value("encoded", false);
  if (j.contains("heads")) {
    for (const auto& [head, pred] : j["heads"].items())
      r.labels.emplace_back(head, lower(pred.value("label", "")));
  }
  return r;
}

GraspRecord old_grasp(const json& j) {
  GraspRecord r;
  r.computed = j.value("computed", false);
  r.reason = j.value("reason", "?");
  for (const json& f : j.value("frames", json::array())) {
    if (f.value("finger", "") == "A" && f.value("moment", "") == "during")
      r.during_seq_a = f.value("seq", int64_t{-1});
  }
  r.success = j.value("prediction", "") == "success";
  return r;
}

}  // namespace

Status read_predictions(const std::string& path, const std::vector<std::string>& fingers,
                        const std::function<Status(const FrameRecord&)>& frame,
                        const std::function<Status(const GraspRecord&)>& grasp) {
  Names names;
  return read_lines(path, [&](const json& j) -> Status {
    const std::string type = j.value("type", "");
    if (type == "hello") read_hello(j, names);
    if (type == "frame_prediction") return frame(frame_prediction(j, names, fingers));
    if (type == "grasp_prediction") return grasp(grasp_prediction(j, names, fingers));
    if (type == "frame") return frame(old_frame(j, fingers));
    if (type == "grasp") return grasp(old_grasp(j));
    return {};
  });
}

}  // namespace tlvlink::score::internal
