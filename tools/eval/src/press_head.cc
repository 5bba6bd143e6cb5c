// A press head from recorded presses (press_head.h).

#include "tlvlink/eval/press_head.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "put_head.h"
#include "tlvlink/eval/trust.h"
#include "tlvlink/io/line_reader.h"
#include "tlvlink/pipeline/press_tracker.h"
#include "tlvlink/quantize/model_copy.h"

namespace tlvlink::eval {
namespace {

using nlohmann::json;

// Calls `each` with every JSON object of a JSON-lines file; errors name the file and line.
template <typename Each>
Status read_json_lines(const std::string& path, Each each) {
  tools::LineReader in;
  TLV_TRY(in.open(path));
  std::string line;
  while (in.next(line)) {
    if (line.empty()) continue;
    const json j = json::parse(line, nullptr, false);
    TLV_ENSURE(!in.too_long() && !j.is_discarded() && j.is_object(), ErrorCode::kFormat,
               "%s:%lld: not a JSON object on one line", path.c_str(),
               static_cast<long long>(in.line_number()));
    if (Status st = each(j); !st.ok())
      return st.error().with_context("%s:%lld", path.c_str(),
                                     static_cast<long long>(in.line_number()));
  }
  return in.error();
}

struct PressEvent {
  int64_t first_seq = 0, last_seq = 0;
  std::string label;
};

struct Scenario {
  std::string sensor;
  std::vector<PressEvent> presses;  // by first_seq
};

Result<Scenario> read_truth(const std::string& path, const std::string& label) {
  Scenario s;
  TLV_TRY(read_json_lines(path, [&](const json& j) -> Status {
    const std::string type = j.value("type", "");
    if (type == "scenario") s.sensor = j.value("sensor", "");
    if (type != "event" || j.value("kind", "") != "press") return {};
    TLV_ENSURE(j.contains("first_seq") && j.contains("last_seq"), ErrorCode::kFormat,
               "a press event without first_seq / last_seq");
    const auto it = j.find(label);
    if (it == j.end() || !it->is_string() || it->get<std::string>().empty()) return {};
    s.presses.push_back(
        {j["first_seq"].get<int64_t>(), j["last_seq"].get<int64_t>(), it->get<std::string>()});
    return {};
  }));
  std::sort(s.presses.begin(), s.presses.end(),
            [](const PressEvent& a, const PressEvent& b) { return a.first_seq < b.first_seq; });
  return s;
}

// The press event a frame falls in, or -1.
int32_t press_of(const Scenario& s, int64_t seq) {
  auto it = std::upper_bound(s.presses.begin(), s.presses.end(), seq,
                             [](int64_t v, const PressEvent& e) { return v < e.first_seq; });
  if (it == s.presses.begin()) return -1;
  --it;
  return seq <= it->last_seq ? static_cast<int32_t>(it - s.presses.begin()) : -1;
}

std::string hex16(uint64_t v) {
  char b[24];
  std::snprintf(b, sizeof b, "%016" PRIx64, v);
  return b;
}

std::string as_percent(double v) {
  char b[16];
  std::snprintf(b, sizeof b, "%.1f", 100.0 * v);
  return b;
}

// Each press's features at the end of its longest contact, fed frame by frame to the board's
// tracker: sensor 0's records, a contact broken by a record out of contact.
class PressReader {
 public:
  PressReader(int32_t dim, const Scenario& s)
      : dim_(dim), scenario_(s), tracker_(dim), best_(s.presses.size()) {}

  Status frame(const json& j) {
    if (j.value("sensor", -1) != 0) return {};
    const bool contact = j.value("contact", false);
    const auto e = j.find("embedding");
    if (!contact) return close();
    TLV_ENSURE(e != j.end() && e->is_array() && e->size() == static_cast<size_t>(dim_),
               ErrorCode::kFormat,
               "a frame in contact without its embedding of %d values (tlvlinkd's `embedding = "
               "true`)",
               dim_);
    const int64_t seq = j.value("frame_sequence", int64_t{-1});
    const int32_t press = press_of(scenario_, seq);
    if (press != current_) TLV_TRY(close());
    current_ = press;
    if (press < 0) return {};  // the gate's false contact between presses
    for (size_t i = 0; i < embedding_.size(); ++i) embedding_[i] = (*e)[i].get<float>();
    tracker_.add(embedding_, j.value("gate_score_dn", 0.0f));
    return {};
  }

  Status close() {
    if (current_ >= 0 && tracker_.frames() > best_[static_cast<size_t>(current_)].frames) {
      Best& b = best_[static_cast<size_t>(current_)];
      b.frames = tracker_.frames();
      b.peak.assign(tracker_.peak().begin(), tracker_.peak().end());
      b.first.assign(tracker_.first().begin(), tracker_.first().end());
    }
    tracker_.restart();
    current_ = -1;
    return {};
  }

  struct Best {
    int32_t frames = 0;
    std::vector<float> peak, first;
  };
  const std::vector<Best>& presses() const { return best_; }

 private:
  int32_t dim_;
  const Scenario& scenario_;
  pipeline::PressTracker tracker_;
  std::vector<float> embedding_ = std::vector<float>(static_cast<size_t>(dim_));
  int32_t current_ = -1;
  std::vector<Best> best_;
};

// The label order: the model's per-frame head of that label's, else the labels seen, sorted.
std::vector<std::string> class_names(const Model& model, const std::string& label,
                                     const std::vector<Scenario>& scenarios) {
  for (const LinearHead& h : model.metadata().linear_heads)
    if (h.name == label) return {h.labels.begin(), h.labels.end()};
  std::set<std::string> seen;
  for (const Scenario& s : scenarios)
    for (const PressEvent& p : s.presses) seen.insert(p.label);
  return {seen.begin(), seen.end()};
}

// One play of a scenario (tlvlinkd's JSON lines) into rows grouped by `group`.
Status read_play(const std::string& path, const Scenario& s, const std::string& checksum,
                 const std::string& group, PressRows& rows) {
  PressReader reader(rows.dim, s);
  bool hello = false;
  TLV_TRY(read_json_lines(path, [&](const json& j) -> Status {
    const std::string type = j.value("type", "");
    if (type == "hello") {
      hello = true;
      const std::string got = j.value("model_checksum", "");
      TLV_ENSURE(got == checksum, ErrorCode::kInvalidArgument,
                 "recorded with a model of checksum %s; this model's is %s: the embeddings are "
                 "another encoder's (record the presses with this model)",
                 got.c_str(), checksum.c_str());
    }
    return type == "frame_prediction" ? reader.frame(j) : Status{};
  }));
  TLV_TRY(reader.close());
  TLV_ENSURE(hello, ErrorCode::kFormat, "%s: no hello record (not tlvlinkd's JSON lines?)",
             path.c_str());
  for (size_t p = 0; p < s.presses.size(); ++p) {
    ++rows.presses;
    const PressReader::Best& b = reader.presses()[p];
    const auto c = std::find(rows.classes.begin(), rows.classes.end(), s.presses[p].label);
    if (b.frames < pipeline::PressTracker::kMinFrames || c == rows.classes.end()) {
      ++rows.short_presses;
      continue;
    }
    rows.features.insert(rows.features.end(), b.peak.begin(), b.peak.end());
    for (size_t i = 0; i < b.peak.size(); ++i) rows.features.push_back(b.peak[i] - b.first[i]);
    rows.peaks.insert(rows.peaks.end(), b.peak.begin(), b.peak.end());
    rows.labels.push_back(static_cast<int32_t>(c - rows.classes.begin()));
    rows.groups.push_back(group);
    rows.press.push_back(static_cast<int32_t>(p));
  }
  return {};
}

}  // namespace

int64_t PressRows::distinct_presses() const {
  std::set<std::pair<std::string, int32_t>> seen;
  for (size_t i = 0; i < labels.size(); ++i) seen.emplace(groups[i], press[i]);
  return static_cast<int64_t>(seen.size());
}

Result<PressRows> read_recorded_presses(const Model& model, const std::vector<std::string>& dirs,
                                        const PressHeadOptions& o) {
  const int32_t dim = model.metadata().embedding_dim;
  TLV_ENSURE(dim > 0, ErrorCode::kModelInvalidMetadata, "the model declares no embedding");
  TLV_ENSURE(!dirs.empty(), ErrorCode::kInvalidArgument, "no recorded presses given");
  const std::string checksum = hex16(model.metadata().provenance.content_checksum);
  std::vector<Scenario> scenarios;
  for (const std::string& dir : dirs) {
    auto s = read_truth(dir + "/truth.jsonl", o.label);
    if (!s.ok()) return s.error().with_context("recorded presses %s", dir.c_str());
    scenarios.push_back(std::move(s).value());
  }
  PressRows rows;
  rows.dim = dim;
  rows.classes = class_names(model, o.label, scenarios);
  TLV_ENSURE(!o.predictions.empty(), ErrorCode::kInvalidArgument, "no predictions file named");
  for (size_t d = 0; d < dirs.size(); ++d) {
    rows.recordings.push_back(dirs[d]);
    rows.sensors.push_back(scenarios[d].sensor);
    for (const std::string& name : o.predictions)
      TLV_TRY(read_play(dirs[d] + "/" + name, scenarios[d], checksum, dirs[d], rows));
  }
  TLV_ENSURE(!rows.labels.empty(), ErrorCode::kInvalidArgument,
             "no press in %zu recordings was seen for %d frames in contact with a '%s' label",
             dirs.size(), pipeline::PressTracker::kMinFrames, o.label.c_str());
  return rows;
}

Result<PressHeadFit> fit_press_head(const Model& model, const std::vector<std::string>& dirs,
                                    const PressHeadOptions& o) {
  TLV_ENSURE(!o.head.empty(), ErrorCode::kInvalidArgument, "heads fit: the head needs a name");
  for (const LinearHead& h : model.metadata().linear_heads)
    TLV_ENSURE(h.name != o.head, ErrorCode::kInvalidArgument,
               "'%s' is a per-frame head of the model: name the press head otherwise",
               o.head.c_str());
  PressHeadFit fit;
  TLV_ASSIGN_OR_RETURN(fit.rows, read_recorded_presses(model, dirs, o));
  const PressRows& r = fit.rows;
  const auto classes = static_cast<int32_t>(r.classes.size());
  const GroupedRows head_rows{r.features, 2 * r.dim, r.labels, classes, r.groups, r.classes};
  const GroupedRows peak_rows{r.peaks, r.dim, r.labels, classes, r.groups, r.classes};
  TLV_ASSIGN_OR_RETURN(fit.head_cv, cross_validate(head_rows, o.cv));
  TLV_ASSIGN_OR_RETURN(fit.baseline_cv, cross_validate(peak_rows, o.cv));
  TLV_ASSIGN_OR_RETURN(FittedProbe p, fit_grouped(head_rows, o.cv));
  fit.l2 = p.l2;
  quantize::LinearHeadSpec& h = fit.head;
  h.name = o.head;
  h.labels = r.classes;
  h.weight = std::move(p.weight);
  h.bias = std::move(p.bias);
  h.features = std::string(kPressFeatures);
  const CvResult& cv = fit.head_cv;
  quantize::HeadTrustSpec& t = h.trust;
  t = cross_validated_trust(cv, fit.baseline_cv, kOneFrameBaseline);
  t.n = r.distinct_presses();  // not rows: a press's plays are not independent trials
  std::string names;
  for (const std::string& d : r.recordings)
    names += (names.empty() ? "" : ", ") + std::filesystem::path(d).filename().string();
  t.test_set = "recorded presses (" + names + "; " + std::to_string(o.predictions.size()) +
               " play(s) each): grouped " + std::to_string(cv.folds) +
               "-fold cross-validation by recording, " + std::to_string(cv.n) + " rows of " +
               std::to_string(t.n) + " presses";
  return fit;
}

Result<std::vector<std::byte>> model_with_press_head(const Model& model,
                                                     const quantize::LinearHeadSpec& head,
                                                     bool* replaced) {
  quantize::MetadataSpec meta = quantize::metadata_spec_from(model.metadata());
  const bool r = put_head(meta.press_heads, head);
  if (replaced != nullptr) *replaced = r;
  return quantize::model_with_metadata(model, meta);
}

std::string format_press_head(const PressHeadFit& fit) {
  const PressRows& r = fit.rows;
  std::string out;
  char b[512];
  std::snprintf(b, sizeof b,
                "presses: %lld labelled in %zu recordings x plays; %lld rows (seen for >= %d "
                "frames in contact), %lld left out\n",
                static_cast<long long>(r.presses), r.recordings.size(),
                static_cast<long long>(r.labels.size()), pipeline::PressTracker::kMinFrames,
                static_cast<long long>(r.short_presses));
  out += b;
  for (size_t d = 0; d < r.recordings.size(); ++d) {
    std::map<int32_t, int64_t> per_class;
    for (size_t i = 0; i < r.labels.size(); ++i)
      if (r.groups[i] == r.recordings[d]) ++per_class[r.labels[i]];
    std::string counts;
    for (const auto& [c, n] : per_class)
      counts += (counts.empty() ? "" : ", ") + r.classes[static_cast<size_t>(c)] + " " +
                std::to_string(n);
    std::snprintf(b, sizeof b, "  %s (%s): %s\n", r.recordings[d].c_str(),
                  r.sensors[d].empty() ? "sensor not named" : r.sensors[d].c_str(), counts.c_str());
    out += b;
  }
  const CvResult& h = fit.head_cv;
  const CvResult& p = fit.baseline_cv;
  std::snprintf(b, sizeof b,
                "grouped %d-fold cross-validation by recording (L2 chosen inside each fitting "
                "fold):\n",
                h.folds);
  out += b;
  std::snprintf(b, sizeof b, "  %-34s accuracy %5s %% [%s, %s]  balanced %5s %%\n",
                "press head (peak, peak - first)", as_percent(h.accuracy).c_str(),
                as_percent(h.ci_low).c_str(), as_percent(h.ci_high).c_str(),
                as_percent(h.balanced_accuracy).c_str());
  out += b;
  std::snprintf(b, sizeof b, "  %-34s accuracy %5s %% [%s, %s]  balanced %5s %%\n",
                "baseline (the peak alone)", as_percent(p.accuracy).c_str(),
                as_percent(p.ci_low).c_str(), as_percent(p.ci_high).c_str(),
                as_percent(p.balanced_accuracy).c_str());
  out += b;
  std::snprintf(b, sizeof b, "  %-34s %5s %%\nfinal fit on every press: L2 %g\n", "majority class",
                as_percent(h.majority).c_str(), fit.l2);
  out += b;
  return out;
}

}  // namespace tlvlink::eval
