// evaluate / evaluate_embeddings: every (method, task) cell on the test split.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>

#include "tlvlink/eval/eval.h"
#include "tlvlink/heads/evaluator.h"
#include "tlvlink/heads/head_math.h"
#include "tlvlink/sim/generate.h"

namespace tlvlink::eval {
namespace {

// Tallies predictions of one cell.
struct Tally {
  std::vector<int64_t> per_class;
  std::vector<uint8_t> item_correct;  // one per labelled item: n and correct follow from it
  int64_t unlabelled = 0;
  explicit Tally(Task task) : per_class(static_cast<size_t>(task_class_count(task)), 0) {}
  void add(int32_t label, int32_t predicted) {
    if (label < 0) {
      ++unlabelled;
      return;
    }
    ++per_class[static_cast<size_t>(label)];
    item_correct.push_back(label == predicted ? 1 : 0);
  }
};

TaskResult cell(Task task, Method method) {
  TaskResult r;
  r.task = task;
  r.method = method;
  r.chance = 1.0 / static_cast<double>(task_class_count(task));
  return r;
}

TaskResult unavailable(Task task, Method method, std::string note) {
  TaskResult r = cell(task, method);
  r.note = std::move(note);
  return r;
}

void finish(TaskResult& r, Tally&& t, std::string source) {
  r.n = static_cast<int64_t>(t.item_correct.size());
  r.correct = std::count(t.item_correct.begin(), t.item_correct.end(), uint8_t{1});
  r.item_correct = std::move(t.item_correct);
  r.unlabelled = t.unlabelled;
  r.source = std::move(source);
  r.available = r.n > 0;
  if (r.n == 0) {
    r.note = "no labelled test item";
    return;
  }
  r.accuracy = static_cast<double>(r.correct) / static_cast<double>(r.n);
  r.majority = static_cast<double>(*std::max_element(t.per_class.begin(), t.per_class.end())) /
               static_cast<double>(r.n);
}

// Head row -> canonical class index, from the head's label names.
template <typename Labels>
Result<std::vector<int32_t>> class_map(Task task, const Labels& labels) {
  std::vector<int32_t> map;
  for (const auto& l : labels) {
    TLV_ASSIGN_OR_RETURN(const int32_t c, task_class_index(task, std::string_view(l)));
    map.push_back(c);
  }
  return map;
}

// A linear or zero-shot head as spans, whatever owns it.
struct HeadView {
  std::string name;
  std::span<const float> weight, bias;  // zero-shot: weight = prompt matrix, bias empty
  float scale = 0;                      // zero-shot logit scale
  std::vector<int32_t> classes;         // row -> canonical class
  bool zero_shot = false;
};

TaskResult score_touch(const TouchEmbeddings& t, Task task, Method method, const HeadView& h,
                       std::string source) {
  TaskResult r = cell(task, method);
  const size_t rows = h.classes.size(), d = static_cast<size_t>(t.dim);
  if (h.weight.size() != rows * d || (!h.zero_shot && h.bias.size() != rows)) {
    r.note = "head '" + h.name + "' does not match the embedding dim " + std::to_string(d);
    return r;
  }
  Tally tally(task);
  std::vector<float> logits(rows);
  const std::vector<int32_t>& labels = t.labels(task);
  for (size_t i = 0; i < t.size(); ++i) {
    if (t.is_test[i] == 0) continue;
    if (labels[i] < 0) {
      tally.add(-1, 0);
      continue;
    }
    if (h.zero_shot)
      heads::zero_shot_logits(h.weight, h.scale, t.row(i), logits);
    else
      heads::linear_logits(h.weight, h.bias, t.row(i), logits);
    tally.add(labels[i], h.classes[static_cast<size_t>(heads::argmax(logits))]);
  }
  finish(r, std::move(tally), std::move(source));
  return r;
}

// The grasp head scoring test episode i (null: leave the episode out).
using GraspHeadFor = std::function<const GraspHead*(size_t)>;

Result<TaskResult> score_grasp_heads(const GraspEmbeddings& g, Method method,
                                     const GraspHeadFor& head_for, std::string source) {
  TaskResult r = cell(Task::kGrasp, method);
  Tally tally(Task::kGrasp);
  for (size_t i = 0; i < g.size(); ++i) {
    if (g.is_test[i] == 0) continue;
    const GraspHead* h = head_for(i);
    if (h == nullptr) continue;
    TLV_ASSIGN_OR_RETURN(const float logit,
                         grasp_head_logit(h->weight, h->bias, h->feature_layout, g, i));
    tally.add(g.label[i], logit > 0 ? 1 : 0);
  }
  finish(r, std::move(tally), std::move(source));
  return r;
}

Result<TaskResult> score_grasp_head(const GraspEmbeddings& g, Method method,
                                    std::span<const float> w, float b, std::string_view layout,
                                    std::string source) {
  GraspHead head;
  head.weight = w;
  head.bias = b;
  head.feature_layout = layout;
  return score_grasp_heads(
      g, method, [&](size_t) { return &head; }, std::move(source));
}

// The head a runtime uses for episode i: the one HeadEvaluator::grasp_head_for picks for the
// episode's recorded sensor (both fingers of an episode carry one sensor model).
const GraspHead* runtime_grasp_head(const heads::HeadEvaluator& h, const GraspEmbeddings& g,
                                    size_t i) {
  return &h.grasp_head(h.grasp_head_for(i < g.sensor.size() ? g.sensor[i] : std::string()));
}

// The model-heads grasp cell as a runtime scores it (each episode by its sensor's head), and
// each head alone on the episodes it is for (the grasp head on all: it is the fallback for any
// sensor), for their trust records.
Status score_model_grasp(const Metadata& m, const GraspEmbeddings& g, EvalReport& rep) {
  TLV_ASSIGN_OR_RETURN(const heads::HeadEvaluator evaluator, heads::HeadEvaluator::create(m));
  const std::string name(m.grasp_head.name);
  std::string source = "model head '" + name + "'";
  if (!m.sensor_grasp_heads.empty())
    source += " and its sensor heads, each episode by its sensor's";
  TLV_ASSIGN_OR_RETURN(TaskResult cell,
                       score_grasp_heads(
                           g, Method::kModelHeads,
                           [&](size_t i) { return runtime_grasp_head(evaluator, g, i); }, source));
  rep.results.push_back(std::move(cell));
  if (m.sensor_grasp_heads.empty()) return {};
  TLV_ASSIGN_OR_RETURN(TaskResult all,
                       score_grasp_heads(
                           g, Method::kModelHeads, [&](size_t) { return &m.grasp_head; },
                           "model head '" + name + "' (any sensor) on every episode"));
  rep.grasp_head_cells.push_back(std::move(all));
  for (const GraspHead& h : m.sensor_grasp_heads) {
    const auto mine = [&](size_t i) {
      return runtime_grasp_head(evaluator, g, i) == &h ? &h : nullptr;
    };
    const auto fallback = [&](size_t i) { return mine(i) != nullptr ? &m.grasp_head : nullptr; };
    std::string sensors;
    for (std::string_view s : h.sensors) sensors += (sensors.empty() ? "" : ",") + std::string(s);
    TLV_ASSIGN_OR_RETURN(TaskResult own,
                         score_grasp_heads(g, Method::kModelHeads, mine,
                                           "sensor head '" + std::string(h.name) + "' (" + sensors +
                                               ") on its sensor's episodes"));
    if (own.n == 0) {  // no episode of its sensor in this set: nothing to say of it
      rep.grasp_head_cells.push_back(std::move(own));
      continue;
    }
    TLV_ASSIGN_OR_RETURN(TaskResult any, score_grasp_heads(g, Method::kModelHeads, fallback, ""));
    char buf[240];
    std::snprintf(buf, sizeof buf,
                  "grasp model heads on %s episodes (n=%lld): its sensor head %.1f %%, the "
                  "any-sensor head %.1f %% (majority %.1f %%)",
                  sensors.c_str(), static_cast<long long>(own.n), 100 * own.accuracy,
                  100 * any.accuracy, 100 * own.majority);
    rep.notes.emplace_back(buf);
    rep.grasp_head_cells.push_back(std::move(own));
  }
  return {};
}

// TLV-Link's grasp zero-shot: logits averaged over fingers A/B x before/after.
TaskResult score_grasp_zero_shot(const GraspEmbeddings& g, const HeadView& h, std::string source) {
  TaskResult r = cell(Task::kGrasp, Method::kZeroShot);
  const size_t rows = h.classes.size(), d = static_cast<size_t>(g.dim);
  if (h.weight.size() != rows * d) {
    r.note = "head '" + h.name + "' does not match the embedding dim " + std::to_string(d);
    return r;
  }
  Tally tally(Task::kGrasp);
  std::vector<float> logits(rows), mean(rows);
  for (size_t i = 0; i < g.size(); ++i) {
    if (g.is_test[i] == 0) continue;
    std::fill(mean.begin(), mean.end(), 0.0f);
    for (int32_t f = 0; f < heads::kFingers; ++f) {
      for (heads::Moment m : {heads::Moment::kBefore, heads::Moment::kAfter}) {
        heads::zero_shot_logits(h.weight, h.scale, g.frame(i, f, m), logits);
        for (size_t k = 0; k < rows; ++k) mean[k] += 0.25f * logits[k];
      }
    }
    tally.add(g.label[i], h.classes[static_cast<size_t>(heads::argmax(mean))]);
  }
  finish(r, std::move(tally), std::move(source));
  return r;
}

std::string probe_source(const FittedProbe& p) {
  char buf[160];
  if (p.validation_accuracy.empty()) {
    std::snprintf(buf, sizeof buf, "probe l2=%g (%s)", p.l2, p.note.c_str());
  } else {
    const auto best = *std::max_element(p.validation_accuracy.begin(), p.validation_accuracy.end());
    std::snprintf(buf, sizeof buf, "probe l2=%g (val acc %.3f on %lld groups)", p.l2, best,
                  static_cast<long long>(p.validation_groups));
  }
  return buf;
}

std::optional<GraspOracle> oracle_for(const GraspEmbeddings& g, int64_t samples) {
  if (samples <= 0 || !g.generator_json) return std::nullopt;
  const nlohmann::json j = nlohmann::json::parse(*g.generator_json, nullptr, false);
  if (j.is_discarded() || !j.is_object() || j.value("generator", "") != "GraspEpisodeGenerator")
    return std::nullopt;
  const std::string sensor = j.value("sensor", "gelsight-mini");
  sim::GraspSetOptions o;
  o.objects = j.value("objects", o.objects);
  o.grasps_per_object = j.value("grasps_per_object", o.grasps_per_object);
  o.sensor = sensor;
  o.markers = j.value("markers", o.markers);
  o.seed = j.value("seed", o.seed);
  auto r = sim::grasp_oracle_report(o, samples);
  if (!r.ok()) return std::nullopt;
  return GraspOracle{r->accuracy,     r->class_friction_accuracy, r->prior_friction_accuracy,
                     r->success_rate, r->majority_rate,           r->samples};
}

Status evaluate_probes(const EmbeddingSet& set, const FittedHeads& fit, EvalReport& rep) {
  for (Task task : kAllTasks) {
    const FittedProbe* probe = nullptr;
    for (const auto& [t, p] : fit.probes)
      if (t == task) probe = &p;
    const bool touch_task = task != Task::kGrasp;
    if ((touch_task && !set.touch) || (!touch_task && !set.grasp)) {
      rep.results.push_back(
          unavailable(task, Method::kProbe, touch_task ? "no touch data" : "no grasp data"));
      continue;
    }
    if (probe == nullptr) {
      std::string note = "not fitted";
      const std::string prefix = std::string(task_name(task)) + ": ";
      for (const std::string& n : fit.notes)
        if (n.rfind(prefix, 0) == 0) note = n.substr(prefix.size());
      rep.results.push_back(unavailable(task, Method::kProbe, note));
      continue;
    }
    if (touch_task) {
      HeadView h{task_name(task), probe->weight, probe->bias, 0, {}, false};
      for (int32_t c = 0; c < task_class_count(task); ++c) h.classes.push_back(c);
      rep.results.push_back(score_touch(*set.touch, task, Method::kProbe, h, probe_source(*probe)));
    } else {
      TLV_ASSIGN_OR_RETURN(
          TaskResult r,
          score_grasp_head(*set.grasp, Method::kProbe, fit.grasp->weight, fit.grasp->bias,
                           fit.grasp->feature_layout, probe_source(*probe)));
      rep.results.push_back(std::move(r));
    }
  }
  return {};
}

Status evaluate_model_heads(const Metadata& m, const EmbeddingSet& set, EvalReport& rep) {
  for (Task task : kAllTasks) {
    if (task == Task::kGrasp) {
      if (!set.grasp) {
        rep.results.push_back(unavailable(task, Method::kModelHeads, "no grasp data"));
      } else if (!m.grasp_head.present) {
        rep.results.push_back(unavailable(task, Method::kModelHeads, "model has no grasp head"));
      } else if (Status st = score_model_grasp(m, *set.grasp, rep); !st.ok()) {
        rep.results.push_back(unavailable(task, Method::kModelHeads, st.error().message()));
      }
      continue;
    }
    if (!set.touch) {
      rep.results.push_back(unavailable(task, Method::kModelHeads, "no touch data"));
      continue;
    }
    const LinearHead* head = nullptr;
    for (const LinearHead& h : m.linear_heads)
      if (auto t = task_of_head(h.name); t.ok() && *t == task) head = &h;
    if (head == nullptr) {
      rep.results.push_back(unavailable(task, Method::kModelHeads,
                                        std::string("model has no ") + task_name(task) + " head"));
      continue;
    }
    auto classes = class_map(task, head->labels);
    if (!classes.ok()) {
      rep.results.push_back(unavailable(task, Method::kModelHeads, classes.error().message()));
      continue;
    }
    HeadView h{std::string(head->name), head->weight, head->bias, 0, *classes, false};
    rep.results.push_back(
        score_touch(*set.touch, task, Method::kModelHeads, h, "model head '" + h.name + "'"));
  }
  return {};
}

Status evaluate_zero_shot(const Metadata& m, const EmbeddingSet& set, const EvalOptions& o,
                          EvalReport& rep) {
  std::optional<TextHeads> text;
  std::string text_error;
  for (Task task : kAllTasks) {
    const bool touch_task = task != Task::kGrasp;
    if ((touch_task && !set.touch) || (!touch_task && !set.grasp)) {
      rep.results.push_back(
          unavailable(task, Method::kZeroShot, touch_task ? "no touch data" : "no grasp data"));
      continue;
    }
    HeadView h;
    h.zero_shot = true;
    std::string source;
    std::optional<Result<std::vector<int32_t>>> classes;
    if (o.zero_shot != ZeroShotSource::kText) {
      for (const ZeroShotHead& z : m.zero_shot_heads) {
        if (auto t = task_of_head(z.name); !t.ok() || *t != task) continue;
        h.name = z.name;
        h.weight = z.prompt_matrix;
        h.scale = z.logit_scale;
        classes.emplace(class_map(task, z.class_names));
        source = "model zero-shot head '" + h.name + "'";
      }
    }
    if (!classes && o.zero_shot != ZeroShotSource::kModel) {
      if (!text && text_error.empty()) {
        auto t = zero_shot_heads_from_text(m, o.text);
        if (t.ok())
          text = std::move(t).value();
        else
          text_error = t.error().message();
      }
      if (text) {
        for (const quantize::ZeroShotHeadSpec& z : text->heads) {
          if (auto t = task_of_head(z.name); !t.ok() || *t != task) continue;
          h.name = z.name;
          h.weight = z.prompt_matrix;
          h.scale = z.logit_scale;
          classes.emplace(class_map(task, z.class_names));
          source = "text " + text->encoder;
        }
      }
    }
    if (!classes) {
      rep.results.push_back(
          unavailable(task, Method::kZeroShot,
                      !text_error.empty()
                          ? "text encoder: " + text_error
                          : std::string("model has no ") + task_name(task) + " zero-shot head"));
      continue;
    }
    if (!classes->ok()) {
      rep.results.push_back(unavailable(task, Method::kZeroShot, classes->error().message()));
      continue;
    }
    h.classes = std::move(*classes).value();
    rep.results.push_back(touch_task ? score_touch(*set.touch, task, Method::kZeroShot, h, source)
                                     : score_grasp_zero_shot(*set.grasp, h, source));
  }
  return {};
}

// A test split holding episodes of both image paths (sim feel --live-path-fraction): each
// grasp cell's accuracy on either path, as a note (the daemon reads the live path).
void add_image_path_notes(const GraspEmbeddings& g, EvalReport& rep) {
  std::vector<uint8_t> test_live;
  for (size_t i = 0; i < g.size(); ++i)
    if (g.is_test[i] != 0) test_live.push_back(i < g.live_path.size() ? g.live_path[i] : 0);
  const auto live = std::count(test_live.begin(), test_live.end(), uint8_t{1});
  if (live == 0 || live == static_cast<std::ptrdiff_t>(test_live.size())) return;
  for (Method m : {Method::kProbe, Method::kModelHeads}) {
    const TaskResult* r = rep.find(Task::kGrasp, m);
    if (r == nullptr || !r->available || r->item_correct.size() != test_live.size()) continue;
    int64_t n[2] = {0, 0}, hits[2] = {0, 0};
    for (size_t i = 0; i < test_live.size(); ++i) {
      ++n[test_live[i]];
      hits[test_live[i]] += r->item_correct[i];
    }
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "grasp %s by image path: live path %.1f %% (n=%lld), dataset JPEG path %.1f %% "
                  "(n=%lld)",
                  method_title(m), 100.0 * static_cast<double>(hits[1]) / static_cast<double>(n[1]),
                  static_cast<long long>(n[1]),
                  100.0 * static_cast<double>(hits[0]) / static_cast<double>(n[0]),
                  static_cast<long long>(n[0]));
    rep.notes.emplace_back(buf);
  }
}

}  // namespace

const char* method_name(Method m) {
  return m == Method::kProbe ? "probe" : m == Method::kModelHeads ? "model-heads" : "zero-shot";
}
const char* method_title(Method m) {
  return m == Method::kProbe        ? "linear probe"
         : m == Method::kModelHeads ? "model's heads"
                                    : "zero-shot";
}

const TaskResult* BoundRow::find(Task task) const {
  for (const TaskResult& r : results)
    if (r.task == task) return &r;
  return nullptr;
}

const TaskResult* EvalReport::find(Task task, Method method) const {
  for (const TaskResult& r : results)
    if (r.task == task && r.method == method) return &r;
  return nullptr;
}

Result<EvalReport> evaluate_embeddings(const Metadata& metadata, const EmbeddingSet& set,
                                       const EvalOptions& options) {
  TLV_ENSURE(set.touch || set.grasp, ErrorCode::kInvalidArgument, "no embeddings to evaluate");
  EvalReport rep;
  rep.model_name = metadata.name;
  rep.executor = executor_kind_name(options.embedder.executor);
  rep.grasp_features = options.heads.grasp_features;
  rep.extract_seconds = set.seconds;
  rep.frames = set.frames;
  if (metadata.provenance.training.find("random-reference") != std::string_view::npos) {
    rep.notes.push_back(
        "the model is the random reference encoder: its stored heads are random and its "
        "accuracies only exercise the pipeline");
  }
  if (set.touch) {
    rep.touch_split = set.touch->split;
    rep.touch_load_summary = set.touch->load_summary;
    rep.touch_format = set.touch->format;
  }
  if (set.grasp) {
    rep.grasp_split = set.grasp->split;
    rep.grasp_load_summary = set.grasp->load_summary;
    rep.grasp_format = set.grasp->format;
  }
  if (options.fit_probes) {
    const auto t0 = std::chrono::steady_clock::now();
    TLV_ASSIGN_OR_RETURN(FittedHeads fit, fit_heads(set, options.heads));
    rep.fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rep.probes = fit.probes;
    TLV_TRY(evaluate_probes(set, fit, rep));
  }
  if (options.model_heads) TLV_TRY(evaluate_model_heads(metadata, set, rep));
  TLV_TRY(evaluate_zero_shot(metadata, set, options, rep));
  if (set.grasp) add_image_path_notes(*set.grasp, rep);
  if (set.grasp) rep.oracle = oracle_for(*set.grasp, options.oracle_samples);
  if (set.grasp && options.oracle_samples > 0) {
    TLV_ASSIGN_OR_RETURN(GraspFramesOracle frames, grasp_frames_oracle(*set.grasp));
    if (frames.available) rep.grasp_frames_oracle = frames;  // real data: no row, no note
  }
  if (set.touch && options.touch_oracles) {
    rep.touch_oracles = touch_oracles(*set.touch);
    // A set with no hidden variables at all (real data) gets no oracle rows rather than notes.
    if (std::none_of(rep.touch_oracles.begin(), rep.touch_oracles.end(),
                     [](const TouchOracle& o) { return o.available; }))
      rep.touch_oracles.clear();
  }
  return rep;
}

Result<EvalReport> evaluate(const Model& model, const EvalData& data, const EvalOptions& options) {
  TLV_ASSIGN_OR_RETURN(EmbeddingSet set, extract_embeddings(model, data, options.embedder));
  TLV_ASSIGN_OR_RETURN(EvalReport report, evaluate_embeddings(model.metadata(), set, options));
  report.touch_dir = data.touch_dir;
  report.grasp_dir = data.grasp_dir;
  return report;
}

}  // namespace tlvlink::eval
