// fit_heads: probes on the train split; model_with_heads: the heads written into a model copy.

#include <array>
#include <functional>
#include <nlohmann/json.hpp>
#include <set>

#include "parallel_items.h"
#include "probe_json.h"
#include "tlvlink/eval/heads.h"
#include "tlvlink/heads/grasp_layout.h"
#include "tlvlink/quantize/model_copy.h"

namespace tlvlink::eval {
namespace {

std::vector<std::string> canonical_labels(Task task) {
  std::vector<std::string> out;
  for (std::string_view c : task_classes(task)) out.emplace_back(c);
  return out;
}

// Why a task cannot be fitted ("" when it can).
std::string unfit_reason(std::span<const int32_t> labels) {
  if (labels.empty()) return "no labelled training rows";
  std::set<int32_t> distinct(labels.begin(), labels.end());
  if (distinct.size() < 2) return "training rows hold one class only";
  return {};
}

// One touch head (task) on the training split of the touch set.
Status fit_touch_head(const TouchEmbeddings& t, Task task, const HeadFitOptions& o,
                      FittedHeads& out) {
  const std::vector<int32_t>& all = t.labels(task);
  std::vector<float> x;
  std::vector<int32_t> y;
  std::vector<std::string> groups;
  std::vector<int64_t> row_of(t.size(), -1);  // t's row -> the probe's row
  std::vector<std::array<int64_t, 2>> pairs;
  for (size_t i = 0; i < t.size(); ++i) {
    if (t.is_test[i] != 0 || all[i] < 0) continue;
    const std::span<const float> r = t.row(i);
    x.insert(x.end(), r.begin(), r.end());
    row_of[i] = static_cast<int64_t>(y.size());
    y.push_back(all[i]);
    groups.push_back(t.group[i]);
    // A re-encoding follows its frame (extract.cc), so the frame's row is already known.
    if (i < t.view_of.size() && t.view_of[i] >= 0 && row_of[static_cast<size_t>(t.view_of[i])] >= 0)
      pairs.push_back({row_of[static_cast<size_t>(t.view_of[i])], row_of[i]});
  }
  if (const std::string why = unfit_reason(y); !why.empty()) {
    out.notes.push_back(std::string(task_name(task)) + ": not fitted, " + why);
    return {};
  }
  ProbeData data{x, t.dim, y, task_class_count(task), groups, pairs};
  ProbeOptions po = o.probe;
  if (auto own = o.view_weight_grid_of.find(task); own != o.view_weight_grid_of.end())
    po.view_weight_grid = own->second;
  auto probe = fit_probe(data, po);
  if (!probe.ok()) return probe.error().with_context("fitting the %s probe", task_name(task));
  out.linear.push_back({task_name(task), canonical_labels(task), probe->weight, probe->bias});
  out.probes.emplace_back(task, std::move(probe).value());
  return {};
}

// A grasp head on the training episodes `use` accepts (probe diagnostics into `probe`); empty
// with a note (`why`) when they hold one class only.
Result<std::optional<quantize::GraspHeadSpec>> fit_grasp_head(
    const GraspEmbeddings& g, const HeadFitOptions& o, const std::string& layout_text,
    std::span<const heads::GraspFeature> layout, const std::function<bool(size_t)>& use,
    std::optional<FittedProbe>& probe_out, std::string& why) {
  std::vector<float> x;
  std::vector<int32_t> y;
  std::vector<std::string> groups;
  for (size_t i = 0; i < g.size(); ++i) {
    if (g.is_test[i] != 0 || !use(i)) continue;
    for (const int32_t swap : {0, 1}) {
      if (swap == 1 && !o.grasp_swap_fingers) break;
      for (const heads::GraspFeature& f : layout) {
        const std::span<const float> e = g.feature(i, f, swap);
        x.insert(x.end(), e.begin(), e.end());
      }
      y.push_back(g.label[i]);
      groups.push_back(g.group[i]);  // both copies in the same validation group
    }
  }
  why = unfit_reason(y);
  if (!why.empty()) return std::optional<quantize::GraspHeadSpec>();
  const auto features = static_cast<int32_t>(heads::layout_values(layout, g.dim));
  ProbeData data{x, features, y, 2, groups, {}};
  auto probe = fit_probe(data, o.probe);
  if (!probe.ok()) return probe.error().with_context("fitting the grasp probe");
  // Two-class softmax == sigmoid of the logit difference: same decision, same probability.
  quantize::GraspHeadSpec h;
  h.name = task_name(Task::kGrasp);
  h.feature_layout = layout_text;
  const size_t f = static_cast<size_t>(features);
  h.weight.resize(f);
  for (size_t i = 0; i < f; ++i) h.weight[i] = probe->weight[f + i] - probe->weight[i];
  h.bias = probe->bias[1] - probe->bias[0];
  probe_out = std::move(probe).value();
  return std::optional<quantize::GraspHeadSpec>(std::move(h));
}

// The grasp head on every training episode (sensor empty) or on one sensor model's.
Status fit_grasp_part(const GraspEmbeddings& g, const HeadFitOptions& o,
                      const std::string& layout_text, std::span<const heads::GraspFeature> layout,
                      const std::string& sensor, FittedHeads& out) {
  std::optional<FittedProbe> probe;
  std::string why;
  const auto use = [&](size_t i) {
    return sensor.empty() || (i < g.sensor.size() && g.sensor[i] == sensor);
  };
  TLV_ASSIGN_OR_RETURN(auto head, fit_grasp_head(g, o, layout_text, layout, use, probe, why));
  if (!head) {
    out.notes.push_back(sensor.empty() ? "grasp: not fitted, " + why
                                       : "grasp: no head for sensor " + sensor + ", " + why);
    return {};
  }
  if (!sensor.empty()) {
    head->sensors = {sensor};
    out.sensor_grasp.push_back(std::move(*head));
    return {};
  }
  out.grasp = std::move(head);
  out.grasp_swap_fingers = o.grasp_swap_fingers;
  out.probes.emplace_back(Task::kGrasp, std::move(*probe));
  return {};
}

// The sensor models of the grasp set's training split when a head per model is wanted (none
// when the split holds one: the grasp head is already that model's).
std::vector<std::string> grasp_sensors(const GraspEmbeddings& g, const HeadFitOptions& o) {
  if (!o.grasp_per_sensor) return {};
  std::set<std::string> sensors;
  for (size_t i = 0; i < g.size() && i < g.sensor.size(); ++i)
    if (g.is_test[i] == 0 && !g.sensor[i].empty()) sensors.insert(g.sensor[i]);
  if (sensors.size() < 2) return {};
  return {sensors.begin(), sensors.end()};
}

void append(FittedHeads& out, FittedHeads&& part) {
  for (auto& h : part.linear) out.linear.push_back(std::move(h));
  if (part.grasp) {
    out.grasp = std::move(part.grasp);
    out.grasp_swap_fingers = part.grasp_swap_fingers;
  }
  for (auto& h : part.sensor_grasp) out.sensor_grasp.push_back(std::move(h));
  for (auto& p : part.probes) out.probes.push_back(std::move(p));
  for (auto& n : part.notes) out.notes.push_back(std::move(n));
}

nlohmann::json probes_json(const FittedHeads& heads, const WriteHeadsOptions& o) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [task, p] : heads.probes) {
    j[task_name(task)] = {{"l2", p.l2},
                          {"validation_accuracy", p.validation_accuracy},
                          {"train_rows", p.train_rows},
                          {"validation_rows", p.validation_rows},
                          {"train_accuracy", p.train_accuracy},
                          {"iterations", p.iterations},
                          {"note", p.note},
                          {"view_weight", p.view_weight},
                          {"view_trials", internal::view_trials_json(p)}};
  }
  if (heads.grasp) {
    j["grasp_feature_layout"] = heads.grasp->feature_layout;
    j["grasp_swap_fingers"] = heads.grasp_swap_fingers;
    std::vector<std::string> sensors;
    for (const quantize::GraspHeadSpec& h : heads.sensor_grasp) sensors.push_back(h.sensors[0]);
    j["grasp_heads_per_sensor"] = sensors;
  }
  j["notes"] = heads.notes;
  if (!o.provenance_note.empty()) j["context"] = o.provenance_note;
  return j;
}

}  // namespace

// Each head's probe is independent of the others': they are fitted side by side on
// options.threads threads (one probe's own fit stays serial: its L2 grid is warm-started in
// order) and put together in a fixed order, so the heads are the same for any thread count.
Result<FittedHeads> fit_heads(const EmbeddingSet& set, const HeadFitOptions& options) {
  const auto wanted = [&](Task t) { return options.only.empty() || options.only.count(t) > 0; };
  std::vector<std::function<Status(FittedHeads&)>> parts;
  if (set.touch) {
    for (Task task : {Task::kMaterial, Task::kHard, Task::kRough}) {
      if (wanted(task))
        parts.emplace_back(
            [&, task](FittedHeads& out) { return fit_touch_head(*set.touch, task, options, out); });
    }
  }
  const size_t grasp_part = parts.size();
  const std::string layout_text = grasp_feature_layout(options.grasp_features);
  std::vector<heads::GraspFeature> layout;  // parsed once, read by every grasp part
  if (set.grasp && wanted(Task::kGrasp)) {
    const GraspEmbeddings& g = *set.grasp;
    TLV_ASSIGN_OR_RETURN(layout, heads::parse_grasp_layout(layout_text));
    TLV_ENSURE(!heads::has_difference(layout) || !g.difference.empty(), ErrorCode::kInvalidArgument,
               "grasp features '%s' read difference features; the grasp set has none (a model "
               "whose input is not 3-channel gives none): use --grasp-features before-during",
               layout_text.c_str());
    std::vector<std::string> sensors = grasp_sensors(g, options);
    sensors.insert(sensors.begin(), std::string());  // first the head for every sensor
    for (const std::string& sensor : sensors)
      parts.emplace_back([&g, &options, &layout_text, &layout, sensor](FittedHeads& out) {
        return fit_grasp_part(g, options, layout_text, layout, sensor, out);
      });
  }
  std::vector<FittedHeads> fitted(parts.size());
  TLV_TRY(internal::run_items(parts.size(), options.threads,
                              [&](size_t i, int32_t) { return parts[i](fitted[i]); }));
  FittedHeads out;
  for (size_t i = 0; i < fitted.size(); ++i) {
    // Heads per sensor model only beside a grasp head for every sensor.
    if (i > grasp_part && !out.grasp) break;
    append(out, std::move(fitted[i]));
  }
  return out;
}

Result<std::vector<std::byte>> model_with_heads(const Model& model, const FittedHeads& heads,
                                                const WriteHeadsOptions& options) {
  const Metadata& src = model.metadata();
  quantize::MetadataSpec meta = quantize::metadata_spec_from(src);
  for (const quantize::LinearHeadSpec& h : heads.linear) {
    bool replaced = false;
    for (quantize::LinearHeadSpec& old : meta.linear_heads) {
      auto ot = task_of_head(old.name), nt = task_of_head(h.name);
      if (ot.ok() && nt.ok() && *ot == *nt) {
        if (options.replace_linear) old = h;
        replaced = true;
      }
    }
    if (!replaced) meta.linear_heads.push_back(h);
  }
  if (heads.grasp && (options.replace_grasp || !meta.has_grasp_head)) {
    meta.has_grasp_head = true;
    meta.grasp_head = *heads.grasp;
    meta.sensor_grasp_heads = heads.sensor_grasp;  // the old ones went with the old grasp head
  }
  std::string text_encoder;
  if (options.add_missing_zero_shot) {
    std::set<Task> have;
    for (const quantize::ZeroShotHeadSpec& h : meta.zero_shot_heads)
      if (auto t = task_of_head(h.name); t.ok()) have.insert(*t);
    if (have.size() < kAllTasks.size()) {
      TLV_ASSIGN_OR_RETURN(TextHeads text, zero_shot_heads_from_text(src, options.text));
      for (quantize::ZeroShotHeadSpec& h : text.heads) {
        auto t = task_of_head(h.name);
        if (t.ok() && have.count(*t) == 0) meta.zero_shot_heads.push_back(std::move(h));
      }
      text_encoder = text.encoder;
    }
  }
  nlohmann::json training =
      nlohmann::json::parse(meta.training_json, nullptr, /*allow_exceptions=*/false);
  if (training.is_discarded() || !training.is_object()) {
    training = nlohmann::json::object();
    if (!meta.training_json.empty()) training["original"] = meta.training_json;
  }
  nlohmann::json fit = probes_json(heads, options);
  if (!text_encoder.empty()) fit["zero_shot_text_encoder"] = text_encoder;
  training["heads_fit"] = std::move(fit);
  meta.training_json = training.dump();
  return quantize::model_with_metadata(model, meta);
}

}  // namespace tlvlink::eval
