// The Table-2-like text table and the JSON form of evaluation reports.

#include <cstdarg>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "probe_json.h"
#include "tlvlink/eval/eval.h"

namespace tlvlink::eval {
namespace {

// The paper's Table 2 (datasets-and-method.md), measured on real data.
constexpr PaperRow kPaper[] = {
    {"TLV-Link linear probe", 0.672, 0.931, 0.847, 0.945},
    {"TLV-Link zero-shot", 0.700, 0.793, 0.778, 0.654},
    {"without curriculum, zero-shot", 0.687, 0.785, 0.768, 0.442},
};
constexpr int kLabelWidth = 34;
constexpr int kCellWidth = 15;

std::string fmt(const char* f, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char* f, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, f);
  std::vsnprintf(buf, sizeof buf, f, ap);
  va_end(ap);
  return buf;
}

std::string pad(std::string s, int width) {
  if (static_cast<int>(s.size()) < width) s.append(static_cast<size_t>(width) - s.size(), ' ');
  return s;
}

// " [2]" when several reports share the table (the header lines say which model is which).
std::string label_of(const EvalReport&, size_t index, size_t count) {
  if (count == 1) return {};
  return " [" + std::to_string(index + 1) + "]";
}

std::string cell_text(const TaskResult* r) {
  if (r == nullptr || !r->available) return "-";
  return fmt("%.1f (n=%lld)", 100.0 * r->accuracy, static_cast<long long>(r->n));
}

std::string split_line(const char* what, const std::string& format,
                       const std::optional<SplitInfo>& s, const std::string& load) {
  if (!s) return {};
  return fmt(
      "  %s (%s) split %s: train %lld items / %lld groups, test %lld items / %lld groups; %s\n",
      what, format.c_str(), s->source.c_str(), static_cast<long long>(s->train_items),
      static_cast<long long>(s->train_groups), static_cast<long long>(s->test_items),
      static_cast<long long>(s->test_groups), load.c_str());
}

std::optional<Discordance> discordance_of(const EvalReport& first, const EvalReport& second, Task t,
                                          Method m) {
  const TaskResult* a = first.find(t, m);
  const TaskResult* b = second.find(t, m);
  if (a == nullptr || b == nullptr) return std::nullopt;
  auto d = discordance(*a, *b);
  if (!d.ok()) return std::nullopt;
  return *d;
}

// Under a comparison's difference row: on how many test items only [1] / only [2] was right,
// and the exact McNemar p of that split (eval.h discordance()).
std::string disagreement_row(const EvalReport& first, const EvalReport& second, Method m) {
  std::string row = pad(std::string("  right only in [1] / [2] (p)"), kLabelWidth);
  bool any = false;
  for (Task t : kAllTasks) {
    const std::optional<Discordance> d = discordance_of(first, second, t, m);
    any = any || d.has_value();
    row += pad(d ? fmt("%lld/%lld (%.2f)", static_cast<long long>(d->only_first),
                       static_cast<long long>(d->only_second), d->p)
                 : "-",
               kCellWidth);
  }
  return any ? row + "\n" : std::string();
}

nlohmann::json result_json(const TaskResult& r) {
  nlohmann::json j = {
      {"task", task_name(r.task)}, {"method", method_name(r.method)}, {"available", r.available}};
  if (r.available) {
    j["accuracy"] = r.accuracy;
    j["n"] = r.n;
    j["correct"] = r.correct;
    j["majority"] = r.majority;
  }
  j["unlabelled"] = r.unlabelled;
  j["chance"] = r.chance;
  j["source"] = r.source;
  if (!r.note.empty()) j["note"] = r.note;
  return j;
}

nlohmann::json split_json(const std::string& format, const std::optional<SplitInfo>& s,
                          const std::string& load) {
  if (!s) return nullptr;
  return {{"format", format},
          {"source", s->source},
          {"train_items", s->train_items},
          {"test_items", s->test_items},
          {"train_groups", s->train_groups},
          {"test_groups", s->test_groups},
          {"load", load}};
}

}  // namespace

std::span<const PaperRow> paper_table2() { return kPaper; }

std::string format_table(std::span<const EvalReport* const> reports, bool paper_rows) {
  std::string out;
  for (size_t i = 0; i < reports.size(); ++i) {
    const EvalReport& r = *reports[i];
    out += fmt(
        "model%s %s (%s executor): %lld frames embedded in %.1f s, probes fitted in %.1f s\n",
        label_of(r, i, reports.size()).c_str(),
        (r.model_path.empty() ? r.model_name : r.model_path + " '" + r.model_name + "'").c_str(),
        r.executor.c_str(), static_cast<long long>(r.frames), r.extract_seconds, r.fit_seconds);
    out += split_line("touch", r.touch_format, r.touch_split, r.touch_load_summary);
    out += split_line("grasp", r.grasp_format, r.grasp_split, r.grasp_load_summary);
  }
  out += "\n" + pad("accuracy % (test split)", kLabelWidth);
  for (Task t : kAllTasks) out += pad(task_title(t), kCellWidth);
  out += "\n";
  for (Method m : {Method::kProbe, Method::kModelHeads, Method::kZeroShot}) {
    for (size_t i = 0; i < reports.size(); ++i) {
      const EvalReport& r = *reports[i];
      if (m == Method::kModelHeads && r.find(Task::kMaterial, m) == nullptr) continue;
      out += pad(method_title(m) + label_of(r, i, reports.size()), kLabelWidth);
      for (Task t : kAllTasks) out += pad(cell_text(r.find(t, m)), kCellWidth);
      out += "\n";
    }
    if (reports.size() == 2) {  // the difference a comparison is about
      std::string row = pad(std::string("  difference [2] - [1]"), kLabelWidth);
      bool any = false;
      for (Task t : kAllTasks) {
        const TaskResult* a = reports[0]->find(t, m);
        const TaskResult* b = reports[1]->find(t, m);
        const bool ok = a && b && a->available && b->available;
        any = any || ok;
        row += pad(ok ? fmt("%+.1f", 100.0 * (b->accuracy - a->accuracy)) : "-", kCellWidth);
      }
      if (any) out += row + "\n" + disagreement_row(*reports[0], *reports[1], m);
    }
  }
  const EvalReport& first = *reports[0];
  out += pad("chance (test majority)", kLabelWidth);
  for (Task t : kAllTasks) {
    const TaskResult* r = first.find(t, Method::kProbe);
    const double chance = 1.0 / task_class_count(t);
    out += pad(r && r->available ? fmt("%.1f (%.1f)", 100 * chance, 100 * r->majority)
                                 : fmt("%.1f", 100 * chance),
               kCellWidth);
  }
  out += "\n";
  if (!first.touch_oracles.empty()) {
    for (const bool hidden : {true, false}) {
      out += pad(hidden ? "oracle: hidden variables" : "oracle: one frame (k-NN estimate)",
                 kLabelWidth);
      for (Task t : {Task::kMaterial, Task::kHard, Task::kRough}) {
        const TouchOracle* o = nullptr;
        for (const TouchOracle& x : first.touch_oracles)
          if (x.task == t) o = &x;
        out += pad(o && o->available
                       ? fmt("%.1f", 100 * (hidden ? o->hidden_accuracy : o->frame_accuracy))
                       : "-",
                   kCellWidth);
      }
      out += "\n";
    }
  }
  if (first.oracle) {
    out += pad("grasp oracle (visible variables)", kLabelWidth) + pad("", 3 * kCellWidth) +
           fmt("%.1f (%lld episodes)\n", 100 * first.oracle->accuracy,
               static_cast<long long>(first.oracle->samples));
    out += pad("grasp oracle (mu via class only)", kLabelWidth) + pad("", 3 * kCellWidth) +
           fmt("%.1f\n", 100 * first.oracle->class_friction_accuracy);
    out += pad("grasp oracle (mu unknown)", kLabelWidth) + pad("", 3 * kCellWidth) +
           fmt("%.1f\n", 100 * first.oracle->prior_friction_accuracy);
  }
  if (first.grasp_frames_oracle) {
    const GraspFramesOracle& g = *first.grasp_frames_oracle;
    out += pad("grasp: mu via class, test split", kLabelWidth) + pad("", 3 * kCellWidth) +
           fmt("%.1f (%lld episodes)\n", 100 * g.class_accuracy, static_cast<long long>(g.n));
    out += pad("grasp: the frames (estimate)", kLabelWidth) + pad("", 3 * kCellWidth) +
           fmt("%.1f\n", 100 * g.frames_accuracy);
  }
  for (const BoundRow& b : first.bounds) {
    out += pad("bound: " + b.label, kLabelWidth);
    for (Task t : kAllTasks) out += pad(cell_text(b.find(t)), kCellWidth);
    out += "\n";
  }
  if (paper_rows) {
    out += "paper (real data), Table 2 — not comparable to simulated data:\n";
    for (const PaperRow& p : kPaper) {
      out += pad(std::string("  ") + p.label, kLabelWidth);
      for (double v : {p.material, p.hard, p.rough, p.grasp})
        out += pad(fmt("%.1f", 100 * v), kCellWidth);
      out += "\n";
    }
  }
  // Notes: unscored items and unavailable cells, once per report.
  for (size_t i = 0; i < reports.size(); ++i) {
    const EvalReport& r = *reports[i];
    const TaskResult* rough = r.find(Task::kRough, Method::kProbe);
    if (rough && rough->unlabelled > 0) {
      out += fmt("note%s: %lld rough/smooth test items are neither rough nor smooth (not scored)\n",
                 label_of(r, i, reports.size()).c_str(), static_cast<long long>(rough->unlabelled));
    }
    for (const TaskResult& c : r.results) {
      const bool no_data = c.note == "no touch data" || c.note == "no grasp data";  // shown as "-"
      if (!c.available && !c.note.empty() && !no_data) {
        out += fmt("note%s: %s %s: %s\n", label_of(r, i, reports.size()).c_str(),
                   method_title(c.method), task_name(c.task), c.note.c_str());
      }
    }
    for (const auto& [task, p] : r.probes) {
      if (!p.converged) {
        out += fmt("note%s: linear probe %s: %s\n", label_of(r, i, reports.size()).c_str(),
                   task_name(task), p.note.c_str());
      }
    }
    for (const std::string& n : r.notes)
      out += fmt("note%s: %s\n", label_of(r, i, reports.size()).c_str(), n.c_str());
    for (const BoundRow& b : r.bounds)
      out += fmt("bound%s '%s': %s '%s' (%s)\n", label_of(r, i, reports.size()).c_str(),
                 b.label.c_str(), b.model_path.c_str(), b.model_name.c_str(),
                 !b.results.empty() && b.results[0].method == Method::kModelHeads
                     ? "its own heads"
                     : "linear probes fitted on this training split");
    if (!r.touch_oracles.empty())
      out +=
          fmt("oracles%s: hidden = from the simulator's recorded variables (hard/soft and "
              "rough/smooth are functions of them); one frame = %d-NN on force, contact area, "
              "gel depth and the texture the gel shows (tools/eval/README.md)\n",
              label_of(r, i, reports.size()).c_str(), kFrameOracleNeighbours);
    if (r.grasp_frames_oracle)
      out +=
          fmt("grasp oracles%s: visible variables / mu via class / mu unknown on fresh "
              "episodes; on the test split, mu via class and the frames = mu through a %d-NN "
              "material vote on both fingers' frame features, force and areas as recorded "
              "(tools/eval/README.md)\n",
              label_of(r, i, reports.size()).c_str(), kFrameOracleNeighbours);
    out += fmt("grasp features%s: %s\n", label_of(r, i, reports.size()).c_str(),
               grasp_features_name(r.grasp_features));
  }
  return out;
}

std::string report_json(std::span<const EvalReport* const> reports) {
  nlohmann::json doc = {{"reports", nlohmann::json::array()}, {"paper", nlohmann::json::array()}};
  if (reports.size() == 2) {  // where [1] and [2] disagree, per cell both scored
    doc["disagreement"] = nlohmann::json::array();
    for (Method m : {Method::kProbe, Method::kModelHeads, Method::kZeroShot}) {
      for (Task t : kAllTasks) {
        if (const auto d = discordance_of(*reports[0], *reports[1], t, m)) {
          doc["disagreement"].push_back({{"task", task_name(t)},
                                         {"method", method_name(m)},
                                         {"right_only_first", d->only_first},
                                         {"right_only_second", d->only_second},
                                         {"mcnemar_p", d->p}});
        }
      }
    }
  }
  for (const EvalReport* r : reports) {
    nlohmann::json j = {
        {"model_name", r->model_name},
        {"model_path", r->model_path},
        {"executor", r->executor},
        {"grasp_features", grasp_features_name(r->grasp_features)},
        {"frames", r->frames},
        {"extract_seconds", r->extract_seconds},
        {"fit_seconds", r->fit_seconds},
        {"touch_split", split_json(r->touch_format, r->touch_split, r->touch_load_summary)},
        {"grasp_split", split_json(r->grasp_format, r->grasp_split, r->grasp_load_summary)},
        {"results", nlohmann::json::array()},
        {"probes", nlohmann::json::object()},
        {"notes", r->notes}};
    for (const TaskResult& c : r->results) j["results"].push_back(result_json(c));
    for (const auto& [task, p] : r->probes) {
      j["probes"][task_name(task)] = {{"l2", p.l2},
                                      {"validation_accuracy", p.validation_accuracy},
                                      {"train_rows", p.train_rows},
                                      {"validation_rows", p.validation_rows},
                                      {"train_accuracy", p.train_accuracy},
                                      {"iterations", p.iterations},
                                      {"converged", p.converged},
                                      {"note", p.note},
                                      {"view_weight", p.view_weight},
                                      {"view_trials", internal::view_trials_json(p)}};
    }
    for (const TouchOracle& o : r->touch_oracles) {
      nlohmann::json oj = {{"task", task_name(o.task)}, {"available", o.available}, {"n", o.n}};
      if (o.available) {
        oj["hidden_accuracy"] = o.hidden_accuracy;
        oj["frame_accuracy"] = o.frame_accuracy;
      } else {
        oj["note"] = o.note;
      }
      j["touch_oracles"].push_back(std::move(oj));
    }
    for (const BoundRow& b : r->bounds) {
      nlohmann::json bj = {{"label", b.label},
                           {"model_path", b.model_path},
                           {"model_name", b.model_name},
                           {"results", nlohmann::json::array()}};
      for (const TaskResult& c : b.results) bj["results"].push_back(result_json(c));
      j["bounds"].push_back(std::move(bj));
    }
    if (r->oracle) {
      j["grasp_oracle"] = {{"accuracy", r->oracle->accuracy},
                           {"class_friction_accuracy", r->oracle->class_friction_accuracy},
                           {"prior_friction_accuracy", r->oracle->prior_friction_accuracy},
                           {"success_rate", r->oracle->success_rate},
                           {"majority_rate", r->oracle->majority_rate},
                           {"samples", r->oracle->samples}};
    }
    if (r->grasp_frames_oracle) {
      const GraspFramesOracle& g = *r->grasp_frames_oracle;
      j["grasp_frames_oracle"] = {{"frames_accuracy", g.frames_accuracy},
                                  {"class_accuracy", g.class_accuracy},
                                  {"majority_rate", g.majority_rate},
                                  {"n", g.n}};
    }
    doc["reports"].push_back(std::move(j));
  }
  for (const PaperRow& p : kPaper) {
    doc["paper"].push_back({{"row", p.label},
                            {"data", "real"},
                            {"material", p.material},
                            {"hard_soft", p.hard},
                            {"rough_smooth", p.rough},
                            {"grasp", p.grasp}});
  }
  return doc.dump(2);
}

}  // namespace tlvlink::eval
