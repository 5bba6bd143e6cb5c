// Live vs offline on the same frames: paired per-frame, per-event and grasp accuracies with
// cluster-bootstrap intervals (compare.h).

#include "tlvlink/score/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <utility>

#include "predictions.h"
#include "truth.h"

namespace tlvlink::score {
namespace {

using internal::json;
using internal::Truth;

// A run's predictions: per finger and frame, the label of every head; per scripted grasp, the
// predicted success.
struct Predictions {
  std::map<std::pair<int32_t, int64_t>, std::map<std::string, std::string>> frames;
  std::map<int32_t, bool> grasps;  // event -> predicted success
};

Result<Predictions> read_predictions(const std::string& path, const Truth& truth,
                                     const std::vector<std::string>& fingers) {
  Predictions p;
  TLV_TRY(internal::read_predictions(
      path, fingers,
      [&](const internal::FrameRecord& f) -> Status {
        if (f.labels.empty() || f.finger < 0 || f.seq < 0) return {};
        auto& labels = p.frames[{f.finger, f.seq % truth.frames}];
        for (const auto& [head, label] : f.labels) labels[head] = label;
        return {};
      },
      [&](const internal::GraspRecord& g) -> Status {
        if (!g.computed) return {};
        const int32_t event = internal::grasp_event(g.during_seq_a, truth);
        if (event >= 0) p.grasps[event] = g.success;
        return {};
      }));
  return p;
}

// Hits of both sides in one cluster (an event, or a grasp).
struct Cluster {
  int64_t live = 0, offline = 0, n = 0;
};

uint64_t splitmix(uint64_t& s) {
  uint64_t z = (s += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

double percentile(std::vector<double>& v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<size_t>(std::floor(q * static_cast<double>(v.size() - 1) + 0.5));
  return v[std::min(i, v.size() - 1)];
}

PairedRate paired(const std::vector<Cluster>& clusters, uint64_t seed, int32_t samples) {
  PairedRate r;
  r.clusters = static_cast<int64_t>(clusters.size());
  for (const Cluster& c : clusters) {
    r.live.hits += c.live;
    r.offline.hits += c.offline;
    r.live.total += c.n;
    r.offline.total += c.n;
  }
  if (clusters.empty() || r.live.total == 0) return r;
  std::vector<double> live, offline, diff;
  uint64_t state = seed;
  for (int32_t b = 0; b < samples; ++b) {
    Cluster sum;
    for (size_t i = 0; i < clusters.size(); ++i) {
      const Cluster& c = clusters[splitmix(state) % clusters.size()];
      sum.live += c.live;
      sum.offline += c.offline;
      sum.n += c.n;
    }
    if (sum.n == 0) continue;
    const double l = static_cast<double>(sum.live) / static_cast<double>(sum.n);
    const double o = static_cast<double>(sum.offline) / static_cast<double>(sum.n);
    live.push_back(l);
    offline.push_back(o);
    diff.push_back(l - o);
  }
  r.live_ci = {percentile(live, 0.025), percentile(live, 0.975)};
  r.offline_ci = {percentile(offline, 0.025), percentile(offline, 0.975)};
  r.difference_low = percentile(diff, 0.025);
  r.difference_high = percentile(diff, 0.975);
  return r;
}

void merge_ratio(Ratio& a, const Ratio& b) {
  a.hits += b.hits;
  a.total += b.total;
}

}  // namespace

void merge_scores(ScoreReport& a, const ScoreReport& b) {
  a.truth_frames += b.truth_frames;
  a.frames += b.frames;
  a.unmatched_frames += b.unmatched_frames;
  a.calibrating += b.calibrating;
  a.truth_contact += b.truth_contact;
  a.missed_contact += b.missed_contact;
  a.missed_light += b.missed_light;
  a.false_contact += b.false_contact;
  a.invisible_contact += b.invisible_contact;
  a.invisible_seen += b.invisible_seen;
  a.invisible_events += b.invisible_events;
  a.encoded += b.encoded;
  merge_ratio(a.contact_events, b.contact_events);
  for (const auto& [kind, m] : b.missed_by_kind) merge_ratio(a.missed_by_kind[kind], m);
  for (const HeadScore& h : b.heads) {
    auto it = std::find_if(a.heads.begin(), a.heads.end(),
                           [&](const HeadScore& x) { return x.head == h.head; });
    if (it == a.heads.end()) {
      a.heads.push_back({h.head, {}, 0, {}, 0, {}});
      it = a.heads.end() - 1;
    }
    merge_ratio(it->frames, h.frames);
    merge_ratio(it->events, h.events);
    it->without_contact += h.without_contact;
    int64_t top = 0;
    for (const auto& [label, n] : h.event_labels) it->event_labels[label] += n;
    for (const auto& [label, n] : it->event_labels) top = std::max(top, n);
    it->majority =
        it->events.total > 0 ? static_cast<double>(top) / static_cast<double>(it->events.total) : 0;
  }
  a.truth_grasps += b.truth_grasps;
  a.truth_grasp_successes += b.truth_grasp_successes;
  a.grasp_records += b.grasp_records;
  a.grasps_computed += b.grasps_computed;
  a.grasps_not_computed += b.grasps_not_computed;
  a.grasps_unmatched += b.grasps_unmatched;
  merge_ratio(a.grasp_accuracy, b.grasp_accuracy);
  for (const auto& [reason, n] : b.not_computed_reasons) a.not_computed_reasons[reason] += n;
  const int32_t s = a.truth_grasp_successes;
  a.grasp_majority = a.truth_grasps > 0
                         ? static_cast<double>(std::max(s, a.truth_grasps - s)) / a.truth_grasps
                         : 0.0;
}

bool LiveOfflineReport::meets_target() const {
  for (const HeadComparison& h : heads) {
    if (std::abs(h.frames.difference()) > kMaxFrameHeadGap) return false;
  }
  return grasps.live.total > 0 && std::abs(grasps.difference()) <= kMaxGraspGap;
}

Result<LiveOfflineReport> compare_live_offline(const std::vector<RunFiles>& runs,
                                               const std::vector<std::string>& fingers,
                                               uint64_t seed, int32_t samples) {
  TLV_ENSURE(!runs.empty() && fingers.size() == 2 && samples >= 100, ErrorCode::kInvalidArgument,
             "compare: %zu runs, %zu finger names, %d bootstrap samples (need >= 1, 2, >= 100)",
             runs.size(), fingers.size(), samples);
  LiveOfflineReport rep;
  rep.bootstrap_samples = samples;
  std::map<std::string, std::vector<Cluster>> frame_clusters, event_clusters;
  std::vector<Cluster> grasp_clusters;
  for (const RunFiles& run : runs) {
    TLV_ENSURE(!run.offline.empty(), ErrorCode::kInvalidArgument,
               "compare: the run of %s has no offline predictions", run.truth.c_str());
    TLV_ASSIGN_OR_RETURN(const Truth truth, internal::read_truth(run.truth));
    TLV_ASSIGN_OR_RETURN(const Predictions live, read_predictions(run.live, truth, fingers));
    TLV_ASSIGN_OR_RETURN(const Predictions offline, read_predictions(run.offline, truth, fingers));
    TLV_ASSIGN_OR_RETURN(const ScoreReport live_score,
                         score_live_run(run.truth, run.live, fingers));
    TLV_ASSIGN_OR_RETURN(const ScoreReport offline_score,
                         score_live_run(run.truth, run.offline, fingers));
    merge_scores(rep.live, live_score);
    merge_scores(rep.offline, offline_score);
    ++rep.runs;
    rep.events += static_cast<int64_t>(truth.events.size());
    // Per head and event: frames both sides labelled while the renderer shows contact, and the
    // last such label of each finger (the daemon's smoothed answer).
    std::map<std::string, std::map<int32_t, Cluster>> frames_of, events_of;
    std::map<std::string,
             std::map<std::pair<int32_t, int32_t>, std::pair<std::string, std::string>>>
        last;
    for (int32_t f = 0; f < 2; ++f) {
      for (int64_t k = 0; k < truth.frames; ++k) {
        const internal::TruthFrame& tf = truth.fingers[f][static_cast<size_t>(k)];
        if (!tf.contact || tf.event < 0) continue;
        const auto l = live.frames.find({f, k});
        const auto o = offline.frames.find({f, k});
        if (l == live.frames.end() || o == offline.frames.end()) continue;
        const internal::TruthEvent& ev = truth.events[static_cast<size_t>(tf.event)];
        for (const auto& [head, want] : ev.labels) {
          if (want.empty()) continue;
          const auto lh = l->second.find(head), oh = o->second.find(head);
          if (lh == l->second.end() || oh == o->second.end()) continue;
          Cluster& c = frames_of[head][tf.event];
          ++c.n;
          c.live += lh->second == want ? 1 : 0;
          c.offline += oh->second == want ? 1 : 0;
          last[head][{tf.event, f}] = {lh->second, oh->second};
        }
      }
    }
    for (auto& [head, events] : frames_of) {
      for (auto& [event, c] : events) frame_clusters[head].push_back(c);
    }
    for (const auto& [head, answers] : last) {
      for (const auto& [key, labels] : answers) {
        const std::string& want = truth.events[static_cast<size_t>(key.first)].labels.at(head);
        Cluster& c = events_of[head][key.first];
        ++c.n;
        c.live += labels.first == want ? 1 : 0;
        c.offline += labels.second == want ? 1 : 0;
      }
    }
    for (auto& [head, events] : events_of) {
      for (auto& [event, c] : events) event_clusters[head].push_back(c);
    }
    for (size_t e = 0; e < truth.events.size(); ++e) {
      const internal::TruthEvent& ev = truth.events[e];
      if (!ev.has_success) continue;
      ++rep.grasps_scripted;
      const auto l = live.grasps.find(static_cast<int32_t>(e));
      const auto o = offline.grasps.find(static_cast<int32_t>(e));
      rep.live_grasps_missing += l == live.grasps.end() ? 1 : 0;
      rep.offline_grasps_missing += o == offline.grasps.end() ? 1 : 0;
      if (l == live.grasps.end() || o == offline.grasps.end()) continue;
      grasp_clusters.push_back(
          {l->second == ev.success ? 1 : 0, o->second == ev.success ? 1 : 0, 1});
    }
  }
  uint64_t stream = seed;
  for (const auto& [head, clusters] : frame_clusters) {
    HeadComparison h;
    h.head = head;
    h.frames = paired(clusters, splitmix(stream), samples);
    h.events = paired(event_clusters[head], splitmix(stream), samples);
    rep.heads.push_back(std::move(h));
  }
  rep.grasps = paired(grasp_clusters, splitmix(stream), samples);
  return rep;
}

const char* reference_name(Reference reference) {
  return reference == Reference::kDatasetCopy ? "dataset" : "offline";
}

std::string format_live_offline(const LiveOfflineReport& r, Reference reference) {
  std::string out;
  char line[512];
  const auto pct = [](double x) { return 100.0 * x; };
  const bool exact = reference == Reference::kExactFrames;
  const char* ref = reference_name(reference);
  std::snprintf(line, sizeof(line),
                "live vs %s: %d scenario(s), %lld events; the same frames through the live image "
                "path (raw camera output, the board's decoder) and %s\n"
                "95 %% intervals: bootstrap over events (%d samples); ",
                exact ? "offline" : "the datasets' copy", r.runs, static_cast<long long>(r.events),
                exact ? "the offline one (the scenes' processed frames replayed: sim scenario "
                        "--offline)"
                      : "as the datasets store them (JPEG q90, 4:2:0: what the datasets' codec "
                        "alone moves)",
                r.bootstrap_samples);
  out += line;
  if (exact) {
    std::snprintf(line, sizeof(line),
                  "targets: per-frame heads within %.0f points, grasps within %.0f\n",
                  100 * kMaxFrameHeadGap, 100 * kMaxGraspGap);
  } else {
    std::snprintf(line, sizeof(line), "the targets apply to the exact frames, not to this copy\n");
  }
  out += line;
  const auto row = [&](const char* what, const std::string& name, const PairedRate& p,
                       double target) {
    std::snprintf(line, sizeof(line),
                  "%-13s %-9s live %5.1f %% [%5.1f, %5.1f]  %s %5.1f %% [%5.1f, %5.1f]  "
                  "live - %s %+5.1f [%+5.1f, %+5.1f]  n %lld (%lld clusters)%s\n",
                  name.c_str(), what, pct(p.live.rate()), pct(p.live_ci.low), pct(p.live_ci.high),
                  ref, pct(p.offline.rate()), pct(p.offline_ci.low), pct(p.offline_ci.high), ref,
                  pct(p.difference()), pct(p.difference_low), pct(p.difference_high),
                  static_cast<long long>(p.live.total), static_cast<long long>(p.clusters),
                  !exact || target <= 0                ? ""
                  : std::abs(p.difference()) <= target ? "  ok"
                                                       : "  OVER TARGET");
    out += line;
  };
  for (const HeadComparison& h : r.heads) {
    row("frames", h.head, h.frames, kMaxFrameHeadGap);
    row("events", h.head, h.events, 0);
  }
  row("", "grasp", r.grasps, kMaxGraspGap);
  std::snprintf(line, sizeof(line),
                "grasps scripted %d: not predicted live %d, %s %d; majority %.1f %%\n",
                r.grasps_scripted, r.live_grasps_missing, ref, r.offline_grasps_missing,
                pct(r.live.grasp_majority));
  out += line;
  const ScoreReport& s = r.live;
  const int64_t open = s.frames - s.truth_contact - s.invisible_contact;
  std::snprintf(
      line, sizeof(line),
      "live contact gate: %lld of %lld events seen (%lld missed); frames in contact "
      "missed %lld of %lld (%.2f %%); false contacts %lld of %lld open-gel frames (%.2f %%)\n",
      static_cast<long long>(s.contact_events.hits), static_cast<long long>(s.contact_events.total),
      static_cast<long long>(s.contact_events.total - s.contact_events.hits),
      static_cast<long long>(s.missed_contact), static_cast<long long>(s.truth_contact),
      s.truth_contact > 0
          ? pct(static_cast<double>(s.missed_contact) / static_cast<double>(s.truth_contact))
          : 0.0,
      static_cast<long long>(s.false_contact), static_cast<long long>(open),
      open > 0 ? pct(static_cast<double>(s.false_contact) / static_cast<double>(open)) : 0.0);
  out += line;
  if (s.invisible_events > 0 || s.invisible_contact > 0) {
    std::snprintf(line, sizeof(line),
                  "  not counted: %lld events / %lld frames in contact the optics cannot show "
                  "(signal < %.1f DN)\n",
                  static_cast<long long>(s.invisible_events),
                  static_cast<long long>(s.invisible_contact), kInvisibleSignalDn);
    out += line;
  }
  if (exact) out += r.meets_target() ? "targets: met\n" : "targets: NOT met\n";
  return out;
}

std::string format_live_offline_json(const LiveOfflineReport& r, Reference reference) {
  const auto paired_json = [](const PairedRate& p) {
    return json{{"live_hits", p.live.hits},
                {"offline_hits", p.offline.hits},
                {"n", p.live.total},
                {"clusters", p.clusters},
                {"live_ci95", {p.live_ci.low, p.live_ci.high}},
                {"offline_ci95", {p.offline_ci.low, p.offline_ci.high}},
                {"difference", p.difference()},
                {"difference_ci95", {p.difference_low, p.difference_high}}};
  };
  json j;
  j["reference"] = reference_name(reference);  // what the "offline" fields measured
  j["runs"] = r.runs;
  j["events"] = r.events;
  j["bootstrap_samples"] = r.bootstrap_samples;
  for (const HeadComparison& h : r.heads) {
    j["heads"][h.head] = {{"frames", paired_json(h.frames)}, {"events", paired_json(h.events)}};
  }
  j["grasps"] = paired_json(r.grasps);
  j["grasps"]["scripted"] = r.grasps_scripted;
  j["grasps"]["live_missing"] = r.live_grasps_missing;
  j["grasps"]["offline_missing"] = r.offline_grasps_missing;
  j["live"] = json::parse(format_score_json(r.live));
  j["offline"] = json::parse(format_score_json(r.offline));
  if (reference == Reference::kExactFrames) j["meets_target"] = r.meets_target();
  return j.dump();
}

}  // namespace tlvlink::score
