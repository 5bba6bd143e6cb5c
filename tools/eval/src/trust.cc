// Trust records from an evaluation report into a model copy (trust.h).

#include "tlvlink/eval/trust.h"

#include <cstdio>

#include "tlvlink/head_trust.h"
#include "tlvlink/quantize/model_copy.h"

namespace tlvlink::eval {

std::string trust_decision_line(const std::string& head, bool replaced,
                                const quantize::HeadTrustSpec& trust,
                                const std::string& below_baseline) {
  const TrustAssessment a = assess_head(trust_view(trust));
  const std::string why = a.below_baseline ? below_baseline
                          : a.level == HeadTrustLevel::kUntrusted
                              ? "it does not beat the majority class by the rule's margin, "
                              : "";
  return "head '" + head + "' (" + (replaced ? "replaced" : "added") + ") " +
         head_trust_level_name(a.level) + ": " + why +
         (a.level == HeadTrustLevel::kTrusted ? "reported by default"
                                              : "left out of the default output");
}

quantize::HeadTrustSpec cross_validated_trust(const CvResult& cv, const CvResult& baseline,
                                              const std::string& baseline_name) {
  quantize::HeadTrustSpec t;
  t.present = true;
  t.accuracy = static_cast<float>(cv.accuracy);
  t.majority = static_cast<float>(cv.majority);
  t.n = cv.n;
  t.balanced_accuracy = static_cast<float>(cv.balanced_accuracy);
  t.ci_low = static_cast<float>(cv.ci_low);
  t.ci_high = static_cast<float>(cv.ci_high);
  t.groups = cv.groups;
  t.baseline_accuracy = static_cast<float>(baseline.accuracy);
  t.baseline = baseline_name;
  return t;
}

HeadTrust trust_view(const quantize::HeadTrustSpec& t) {
  HeadTrust v;
  v.present = t.present;
  v.accuracy = t.accuracy;
  v.majority = t.majority;
  v.n = t.n;
  v.test_set = t.test_set;
  v.balanced_accuracy = t.balanced_accuracy;
  v.ci_low = t.ci_low;
  v.ci_high = t.ci_high;
  v.groups = t.groups;
  v.baseline_accuracy = t.baseline_accuracy;
  v.baseline = t.baseline;
  return v;
}

namespace {

// The head's cell in the report, if scored.
const TaskResult* scored(const EvalReport& r, std::string_view head_name, Method method) {
  auto task = task_of_head(head_name);
  if (!task.ok()) return nullptr;
  const TaskResult* c = r.find(*task, method);
  return c != nullptr && c->available ? c : nullptr;
}

quantize::HeadTrustSpec record_of(const EvalReport& r, const TaskResult& c) {
  quantize::HeadTrustSpec t;
  t.present = true;
  t.accuracy = static_cast<float>(c.accuracy);
  t.majority = static_cast<float>(c.majority);
  t.n = c.n;
  t.test_set = test_set_description(r, c.task);
  return t;
}

std::string line_of(const std::string& kind, const std::string& name,
                    const quantize::HeadTrustSpec& t, bool dropped) {
  const TrustAssessment a = assess_head(trust_view(t));
  char buf[256];
  if (!t.present) {
    std::snprintf(buf, sizeof buf, "%s head '%s': not measured", kind.c_str(), name.c_str());
  } else {
    std::snprintf(buf, sizeof buf,
                  "%s head '%s': accuracy %.1f %% vs majority %.1f %% (n=%lld): %s "
                  "(margin %+.1f, needs %+.1f)%s",
                  kind.c_str(), name.c_str(), 100.0 * static_cast<double>(t.accuracy),
                  100.0 * static_cast<double>(t.majority), static_cast<long long>(t.n),
                  head_trust_level_name(a.level), 100 * a.margin, 100 * a.required,
                  dropped ? "; removed" : "");
  }
  return buf;
}

}  // namespace

std::string test_set_description(const EvalReport& r, Task task) {
  const bool grasp = task == Task::kGrasp;
  const std::optional<SplitInfo>& s = grasp ? r.grasp_split : r.touch_split;
  const std::string& dir = grasp ? r.grasp_dir : r.touch_dir;
  const std::string& format = grasp ? r.grasp_format : r.touch_format;
  char buf[320];
  std::snprintf(buf, sizeof buf, "%s: %s (%s) test split (%s): %lld items, %lld %s",
                grasp ? "grasp" : "touch", dir.empty() ? "?" : dir.c_str(), format.c_str(),
                s ? s->source.c_str() : "?", s ? static_cast<long long>(s->test_items) : 0LL,
                s ? static_cast<long long>(s->test_groups) : 0LL, grasp ? "objects" : "sessions");
  return buf;
}

Result<std::vector<std::byte>> model_with_trust(const Model& model, const EvalReport& report,
                                                const TrustRecordOptions& options,
                                                std::vector<std::string>* lines) {
  quantize::MetadataSpec meta = quantize::metadata_spec_from(model.metadata());
  std::vector<std::string> out;
  for (quantize::LinearHeadSpec& h : meta.linear_heads) {
    if (const TaskResult* c = scored(report, h.name, Method::kModelHeads))
      h.trust = record_of(report, *c);
    out.push_back(line_of("linear", h.name, h.trust, false));
  }
  if (meta.has_grasp_head) {
    // With sensor heads, each record is the head's own (evaluate.cc score_model_grasp).
    const bool own = report.grasp_head_cells.size() == 1 + meta.sensor_grasp_heads.size();
    if (own) {
      meta.grasp_head.trust = record_of(report, report.grasp_head_cells[0]);
    } else if (const TaskResult* c = scored(report, meta.grasp_head.name, Method::kModelHeads)) {
      meta.grasp_head.trust = record_of(report, *c);
    }
    out.push_back(line_of("grasp", meta.grasp_head.name, meta.grasp_head.trust, false));
    for (size_t h = 0; h < meta.sensor_grasp_heads.size(); ++h) {
      quantize::GraspHeadSpec& g = meta.sensor_grasp_heads[h];
      // A set without this head's sensor says nothing of it: its record stays.
      if (own && report.grasp_head_cells[h + 1].n > 0) {
        g.trust = record_of(report, report.grasp_head_cells[h + 1]);
        g.trust.test_set += " (" + g.sensors[0] + " episodes)";
      }
      out.push_back(line_of("grasp", g.name + " (" + g.sensors[0] + ")", g.trust, false));
    }
  }
  std::vector<quantize::ZeroShotHeadSpec> kept;
  for (quantize::ZeroShotHeadSpec& h : meta.zero_shot_heads) {
    if (const TaskResult* c = scored(report, h.name, Method::kZeroShot))
      h.trust = record_of(report, *c);
    const bool drop = options.drop_untrusted_zero_shot && h.trust.present &&
                      assess_head(trust_view(h.trust)).level == HeadTrustLevel::kUntrusted;
    out.push_back(line_of("zero-shot", h.name, h.trust, drop));
    if (!drop) kept.push_back(std::move(h));
  }
  meta.zero_shot_heads = std::move(kept);
  TLV_ASSIGN_OR_RETURN(std::vector<std::byte> bytes, quantize::model_with_metadata(model, meta));
  if (lines != nullptr) *lines = std::move(out);
  return bytes;
}

}  // namespace tlvlink::eval
