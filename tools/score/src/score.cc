#include "tlvlink/score/score.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>

#include "predictions.h"
#include "truth.h"

namespace tlvlink::score {
namespace {

using internal::json;
using internal::lower;
using internal::read_truth;
using internal::Truth;
using internal::TruthEvent;
using internal::TruthFrame;

}  // namespace

Interval wilson95(const Ratio& r) {
  if (r.total <= 0) return {};
  constexpr double z = 1.959963984540054;
  const double n = static_cast<double>(r.total), p = r.rate(), z2n = z * z / n;
  const double centre = (p + z2n / 2) / (1 + z2n);
  const double half = z * std::sqrt(p * (1 - p) / n + z2n / (4 * n)) / (1 + z2n);
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

Result<ScoreReport> score_live_run(const std::string& truth_path,
                                   const std::string& predictions_path,
                                   const std::vector<std::string>& fingers) {
  TLV_ENSURE(fingers.size() == 2, ErrorCode::kInvalidArgument,
             "score: two sensor names (finger A, finger B) are needed, %zu given", fingers.size());
  TLV_ASSIGN_OR_RETURN(const Truth truth, read_truth(truth_path));
  ScoreReport r;
  r.truth_frames = truth.frames;
  // Per head: frame hits; the last label per (event, finger).
  std::map<std::string, Ratio> head_frames;
  std::map<std::string, int64_t> head_no_contact;
  std::map<std::string, std::map<std::pair<int32_t, int32_t>, std::string>> last_label;
  std::set<int32_t> events_seen_contact, events_played, events_visible;
  const auto on_frame = [&](const internal::FrameRecord& f) -> Status {
    if (f.finger < 0) {
      ++r.unmatched_frames;
      return {};
    }
    TLV_ENSURE(f.seq >= 0, ErrorCode::kFormat, "frame record without a sequence");
    const TruthFrame& tf = truth.fingers[f.finger][static_cast<size_t>(f.seq % truth.frames)];
    const bool gated_contact = f.gate == internal::Gate::kContact;
    if (f.gate == internal::Gate::kCalibrating) {  // learning the reference: no decision yet
      ++r.calibrating;
      return {};
    }
    ++r.frames;
    r.encoded += f.encoded ? 1 : 0;
    if (tf.event >= 0) events_played.insert(tf.event);
    const bool invisible = tf.contact && tf.signal_dn < kInvisibleSignalDn;
    if (invisible) {  // nothing a camera can see: counted apart, not a miss of the gate
      ++r.invisible_contact;
      r.invisible_seen += gated_contact ? 1 : 0;
    } else if (tf.contact) {
      ++r.truth_contact;
      if (!gated_contact) {
        ++r.missed_contact;
        r.missed_light += tf.force_n < 1.0 ? 1 : 0;
      } else if (tf.event >= 0) {
        events_seen_contact.insert(tf.event);
      }
      if (tf.event >= 0) {
        events_visible.insert(tf.event);
        Ratio& k = r.missed_by_kind[truth.events[static_cast<size_t>(tf.event)].kind];
        ++k.total;
        k.hits += gated_contact ? 0 : 1;
      }
    } else if (gated_contact) {
      ++r.false_contact;
    }
    if (tf.event < 0) return {};
    const TruthEvent& ev = truth.events[static_cast<size_t>(tf.event)];
    for (const auto& [head, got] : f.labels) {
      auto want = ev.labels.find(head);
      if (want == ev.labels.end() || want->second.empty()) continue;
      if (!tf.contact) {  // nothing on the gel: a label of the gate's false contact, not of the
                          // object
        ++head_no_contact[head];
        continue;
      }
      Ratio& hr = head_frames[head];
      ++hr.total;
      hr.hits += got == want->second ? 1 : 0;
      last_label[head][{tf.event, f.finger}] = got;
    }
    return {};
  };
  const auto on_grasp = [&](const internal::GraspRecord& g) -> Status {
    ++r.grasp_records;
    if (!g.computed) {
      ++r.grasps_not_computed;
      ++r.not_computed_reasons[g.reason];
      return {};
    }
    const int32_t event =
        g.during_seq_a >= 0
            ? truth.fingers[0][static_cast<size_t>(g.during_seq_a % truth.frames)].event
            : -1;
    if (event < 0 || !truth.events[static_cast<size_t>(event)].has_success) {
      ++r.grasps_unmatched;
      return {};
    }
    ++r.grasps_computed;
    ++r.grasp_accuracy.total;
    r.grasp_accuracy.hits += g.success == truth.events[static_cast<size_t>(event)].success ? 1 : 0;
    return {};
  };
  TLV_TRY(internal::read_predictions(predictions_path, fingers, on_frame, on_grasp));
  // Events in the frames that were played.
  int32_t successes = 0;
  for (int32_t e : events_played) {
    const TruthEvent& ev = truth.events[static_cast<size_t>(e)];
    if (events_visible.count(e) > 0) {
      ++r.contact_events.total;
      r.contact_events.hits += events_seen_contact.count(e) > 0 ? 1 : 0;
    } else {
      ++r.invisible_events;
    }
    if (ev.has_success) {
      ++r.truth_grasps;
      successes += ev.success ? 1 : 0;
    }
  }
  r.truth_grasp_successes = successes;
  r.grasp_majority =
      r.truth_grasps > 0
          ? static_cast<double>(std::max(successes, r.truth_grasps - successes)) / r.truth_grasps
          : 0.0;
  for (const auto& [head, n] : head_no_contact) head_frames.try_emplace(head);
  for (const auto& [head, frames] : head_frames) {
    HeadScore h;
    h.head = head;
    h.frames = frames;
    h.without_contact = head_no_contact.count(head) > 0 ? head_no_contact.at(head) : 0;
    std::map<std::string, int64_t> counts;
    for (const auto& [key, got] : last_label[head]) {
      const std::string& want = truth.events[static_cast<size_t>(key.first)].labels.at(head);
      ++h.events.total;
      h.events.hits += got == want ? 1 : 0;
      ++counts[want];
    }
    int64_t top = 0;
    for (const auto& [label, n] : counts) top = std::max(top, n);
    h.event_labels = counts;
    h.majority =
        h.events.total > 0 ? static_cast<double>(top) / static_cast<double>(h.events.total) : 0.0;
    r.heads.push_back(std::move(h));
  }
  return r;
}

std::string format_score(const ScoreReport& r) {
  std::string out;
  char line[512];
  const auto pct = [](const Ratio& x) { return 100.0 * x.rate(); };
  std::snprintf(
      line, sizeof(line),
      "frames scored: %lld (scenario: %lld per finger; %lld more while the gate calibrated)\n"
      "contact gating: %lld frames in contact, %lld missed (%.2f %%; %lld of them under "
      "1 N), %lld false contacts; encoder ran on %lld of %lld frames (%.1f %% saved); "
      "events touched and seen: %lld/%lld\n",
      static_cast<long long>(r.frames), static_cast<long long>(r.truth_frames),
      static_cast<long long>(r.calibrating), static_cast<long long>(r.truth_contact),
      static_cast<long long>(r.missed_contact),
      r.truth_contact > 0
          ? 100.0 * static_cast<double>(r.missed_contact) / static_cast<double>(r.truth_contact)
          : 0.0,
      static_cast<long long>(r.missed_light), static_cast<long long>(r.false_contact),
      static_cast<long long>(r.encoded), static_cast<long long>(r.frames),
      r.frames > 0 ? 100.0 * (1.0 - static_cast<double>(r.encoded) / static_cast<double>(r.frames))
                   : 0.0,
      static_cast<long long>(r.contact_events.hits),
      static_cast<long long>(r.contact_events.total));
  out += line;
  if (r.invisible_contact > 0) {
    std::snprintf(line, sizeof(line),
                  "  contacts the optics cannot show (signal < %.1f DN: smooth flat faces filling "
                  "the gel): %lld frames (%lld gated as contact), %lld events; not counted above\n",
                  kInvisibleSignalDn, static_cast<long long>(r.invisible_contact),
                  static_cast<long long>(r.invisible_seen),
                  static_cast<long long>(r.invisible_events));
    out += line;
  }
  for (const auto& [kind, m] : r.missed_by_kind) {
    std::snprintf(line, sizeof(line),
                  "  missed in %s scenes: %lld of %lld frames in contact (%.2f %%)\n", kind.c_str(),
                  static_cast<long long>(m.hits), static_cast<long long>(m.total), pct(m));
    out += line;
  }
  for (const HeadScore& h : r.heads) {
    const Interval ci = wilson95(h.events);
    std::snprintf(line, sizeof(line),
                  "%-13s per frame %5.1f %% (%lld/%lld)   per event %5.1f %% (%lld/%lld, 95 %% CI "
                  "%.1f-%.1f; majority %.1f %%)\n",
                  h.head.c_str(), pct(h.frames), static_cast<long long>(h.frames.hits),
                  static_cast<long long>(h.frames.total), pct(h.events),
                  static_cast<long long>(h.events.hits), static_cast<long long>(h.events.total),
                  100.0 * ci.low, 100.0 * ci.high, 100.0 * h.majority);
    out += line;
    if (h.without_contact > 0) {
      std::snprintf(line, sizeof(line), "  %s: %lld labelled frames without contact not scored\n",
                    h.head.c_str(), static_cast<long long>(h.without_contact));
      out += line;
    }
  }
  std::snprintf(line, sizeof(line),
                "grasps: %d scripted, %d records: %d computed (%d matched to no grasp), %d not "
                "computed; success predicted right %lld/%lld (%.1f %%, 95 %% CI %.1f-%.1f; "
                "majority %.1f %%)\n",
                r.truth_grasps, r.grasp_records, r.grasps_computed + r.grasps_unmatched,
                r.grasps_unmatched, r.grasps_not_computed,
                static_cast<long long>(r.grasp_accuracy.hits),
                static_cast<long long>(r.grasp_accuracy.total), pct(r.grasp_accuracy),
                100.0 * wilson95(r.grasp_accuracy).low, 100.0 * wilson95(r.grasp_accuracy).high,
                100.0 * r.grasp_majority);
  out += line;
  for (const auto& [reason, n] : r.not_computed_reasons) {
    std::snprintf(line, sizeof(line), "  not computed x%d: %s\n", n, reason.c_str());
    out += line;
  }
  return out;
}

std::string format_score_json(const ScoreReport& r) {
  json j;
  j["frames"] = r.frames;
  j["calibrating"] = r.calibrating;
  j["truth_frames"] = r.truth_frames;
  j["contact"] = {{"truth_contact", r.truth_contact},
                  {"missed", r.missed_contact},
                  {"missed_under_1n", r.missed_light},
                  {"false_contact", r.false_contact},
                  {"encoded", r.encoded},
                  {"invisible_frames", r.invisible_contact},
                  {"invisible_seen", r.invisible_seen},
                  {"invisible_events", r.invisible_events},
                  {"events_seen", r.contact_events.hits},
                  {"events", r.contact_events.total}};
  for (const auto& [kind, m] : r.missed_by_kind)
    j["contact"]["missed_by_kind"][kind] = {{"missed", m.hits}, {"frames", m.total}};
  for (const HeadScore& h : r.heads) {
    const Interval ci = wilson95(h.events);
    j["heads"][h.head] = {{"frame_hits", h.frames.hits},
                          {"frames", h.frames.total},
                          {"without_contact", h.without_contact},
                          {"event_hits", h.events.hits},
                          {"events", h.events.total},
                          {"event_ci95", {ci.low, ci.high}},
                          {"majority", h.majority}};
  }
  j["grasps"] = {{"scripted", r.truth_grasps},
                 {"records", r.grasp_records},
                 {"computed", r.grasps_computed},
                 {"unmatched", r.grasps_unmatched},
                 {"not_computed", r.grasps_not_computed},
                 {"hits", r.grasp_accuracy.hits},
                 {"scored", r.grasp_accuracy.total},
                 {"ci95", {wilson95(r.grasp_accuracy).low, wilson95(r.grasp_accuracy).high}},
                 {"majority", r.grasp_majority},
                 {"reasons", r.not_computed_reasons}};
  return j.dump();
}

}  // namespace tlvlink::score
