// The stability suite: one touch through every image path, embeddings and head answers compared
// with the reference path's.

#include "tlvlink/eval/stability.h"

#include "data_paths.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <nlohmann/json.hpp>

#include "tlvlink/heads/evaluator.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/model_input.h"
#include "tlvlink/sim/generate.h"

namespace tlvlink::eval {
namespace {

double cosine(std::span<const float> a, std::span<const float> b) {
  double ab = 0, aa = 0, bb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const auto x = static_cast<double>(a[i]), y = static_cast<double>(b[i]);
    ab += x * y;
    aa += x * x;
    bb += y * y;
  }
  if (aa == 0 || bb == 0) return aa == bb ? 1.0 : 0.0;
  return ab / std::sqrt(aa * bb);
}

// Cosines and head answers of one path, gathered item by item.
struct PathTally {
  std::string source, path;
  std::vector<double> cosines;
  std::vector<std::string> items;
  std::vector<HeadAgreement> heads;
};

// Runs the model and its per-frame heads on frames; keeps the reference item's results.
class Probe {
 public:
  static Result<Probe> create(const Model& model, const EmbedderOptions& options) {
    Probe p;
    TLV_ASSIGN_OR_RETURN(p.embedder_, Embedder::create(model, options));
    TLV_ASSIGN_OR_RETURN(HeadEvaluator heads, heads::HeadEvaluator::create(model.metadata()));
    p.heads_ = std::make_unique<heads::HeadEvaluator>(std::move(heads));
    p.reference_.resize(static_cast<size_t>(p.embedder_->dim()));
    p.current_.resize(p.reference_.size());
    return p;
  }

  // The reference frame of an item.
  Status reference(const sim::RgbImage& frame) {
    TLV_TRY(run(frame, reference_));
    reference_tops_.clear();
    // Per-frame heads only: a press head reads a press, not one frame.
    for (const heads::HeadResult& r : heads_->results().first(heads_->per_frame_count()))
      reference_tops_.push_back(r.top);
    return {};
  }

  // One path's frame of the same item, tallied into `t`.
  Status compare(const sim::RgbImage& frame, const std::string& item, PathTally& t) {
    TLV_TRY(run(frame, current_));
    t.cosines.push_back(cosine(reference_, current_));
    t.items.push_back(item);
    const auto results = heads_->results().first(heads_->per_frame_count());
    if (t.heads.empty()) {
      for (const heads::HeadResult& r : results) {
        t.heads.push_back({std::string(r.name), heads::reported_by_default(r), 0, 0});
      }
    }
    for (size_t h = 0; h < results.size(); ++h) {
      ++t.heads[h].n;
      if (results[h].top == reference_tops_[h]) ++t.heads[h].same;
    }
    return {};
  }

 private:
  using HeadEvaluator = heads::HeadEvaluator;
  Status run(const sim::RgbImage& frame, std::vector<float>& out) {
    TLV_TRY(embedder_->embed(frame, out));
    return heads_->evaluate(out);
  }
  std::unique_ptr<Embedder> embedder_;
  std::unique_ptr<heads::HeadEvaluator> heads_;
  std::vector<float> reference_, current_;
  std::vector<int32_t> reference_tops_;
};

sim::RgbImage offset_path(const sim::RgbImage& frame, int32_t dn) {
  sim::RgbImage out = frame;
  for (uint8_t& v : out.rgb) v = static_cast<uint8_t>(std::clamp(v + dn, 0, 255));
  return out;
}

PathTally& tally(std::vector<PathTally>& all, const std::string& source, const std::string& path) {
  for (PathTally& t : all) {
    if (t.source == source && t.path == path) return t;
  }
  all.push_back({source, path, {}, {}, {}});
  return all.back();
}

Status simulated_scenes(const StabilityOptions& o, Probe& probe, std::vector<PathTally>& all) {
  sim::TouchSetOptions to;
  to.sessions = o.scenes;
  to.frames_per_session = 1;
  to.sensor = o.sensors;
  to.markers_fraction = o.markers_fraction;
  to.seed = o.seed;
  to.sensor_instances = o.sensor_instances;
  to.vision_height = 24;  // the vision image is not used
  to.vision_width = 32;
  TLV_ASSIGN_OR_RETURN(auto generator, sim::TouchSampleGenerator::create(to));
  internal::LivePaths live;
  sim::TouchSample s;
  for (int64_t i = 0; i < generator->size(); ++i) {
    TLV_TRY(generator->generate(i, s));
    char item[96];
    std::snprintf(item, sizeof(item), "scene %lld (%s, instance %d)", static_cast<long long>(i),
                  s.sensor.c_str(), s.sensor_instance);
    TLV_TRY(probe.reference(s.touch));
    for (int32_t q : {95, 90, 75}) {
      TLV_ASSIGN_OR_RETURN(const sim::RgbImage j, internal::jpeg_path(s.touch, q));
      TLV_TRY(probe.compare(j, item, tally(all, "simulated", "jpeg-q" + std::to_string(q))));
    }
    sim::RgbImage l = s.touch;
    TLV_TRY(live.apply(s.sensor, l.rgb));
    TLV_TRY(probe.compare(l, item, tally(all, "simulated", "live " + s.sensor)));
  }
  return {};
}

Status real_frames(const std::string& dir, Probe& probe, std::vector<PathTally>& all,
                   int64_t& count) {
  std::vector<std::string> files;
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    if (!it->is_regular_file()) continue;
    std::string ext = it->path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") files.push_back(it->path().string());
  }
  TLV_ENSURE(!ec, ErrorCode::kIo, "%s: %s", dir.c_str(), ec.message().c_str());
  std::sort(files.begin(), files.end());
  for (const std::string& f : files) {
    TLV_ASSIGN_OR_RETURN(const std::vector<std::byte> bytes, tools::read_file(f, size_t{64} << 20));
    TLV_ASSIGN_OR_RETURN(tools::Image image, tools::decode_image_file(bytes, f));
    if (image.channels != 3) continue;  // gray frames are no GelSight frames
    const sim::RgbImage frame{image.height, image.width, std::move(image.pixels)};
    const std::string item = std::filesystem::relative(f, dir).string();
    TLV_TRY(probe.reference(frame));
    for (int32_t q : {95, 90, 75}) {
      TLV_ASSIGN_OR_RETURN(const sim::RgbImage j, internal::jpeg_path(frame, q));
      TLV_TRY(probe.compare(j, item, tally(all, "real", "jpeg-q" + std::to_string(q))));
    }
    TLV_TRY(probe.compare(offset_path(frame, 3), item, tally(all, "real", "+3 DN")));
    TLV_TRY(probe.compare(offset_path(frame, -3), item, tally(all, "real", "-3 DN")));
    ++count;
  }
  return {};
}

PathStability summarise(const PathTally& t) {
  PathStability p;
  p.source = t.source;
  p.path = t.path;
  p.n = static_cast<int64_t>(t.cosines.size());
  p.heads = t.heads;
  if (p.n == 0) return p;
  const auto worst = std::min_element(t.cosines.begin(), t.cosines.end());
  p.cos_min = *worst;
  p.worst = t.items[static_cast<size_t>(worst - t.cosines.begin())];
  std::vector<double> sorted = t.cosines;
  std::sort(sorted.begin(), sorted.end());
  const auto at = [&](double q) {
    return sorted[std::min(sorted.size() - 1,
                           static_cast<size_t>(q * static_cast<double>(sorted.size())))];
  };
  p.cos_p05 = at(0.05);
  p.cos_median = at(0.5);
  return p;
}

}  // namespace

bool PathStability::meets_target() const {
  if (n == 0 || cos_min < kStabilityMinCosine) return false;
  return std::all_of(heads.begin(), heads.end(), [](const HeadAgreement& h) {
    return !h.trusted || h.rate() >= kStabilityMinAgreement;
  });
}

bool StabilityReport::meets_target() const {
  return !paths.empty() && std::all_of(paths.begin(), paths.end(),
                                       [](const PathStability& p) { return p.meets_target(); });
}

Result<StabilityReport> measure_stability(const Model& model, const StabilityOptions& o) {
  TLV_ENSURE(o.scenes >= 0 && o.scenes <= 100000, ErrorCode::kInvalidArgument,
             "stability: %d scenes (0..100000)", o.scenes);
  TLV_ASSIGN_OR_RETURN(Probe probe, Probe::create(model, o.embedder));
  StabilityReport report;
  report.model = std::string(model.metadata().name);
  report.scenes = o.scenes;
  std::vector<PathTally> all;
  if (o.scenes > 0) TLV_TRY(simulated_scenes(o, probe, all));
  if (o.real_frames_dir.empty()) {
    report.real_note = "no real frames given";
  } else if (!std::filesystem::is_directory(o.real_frames_dir)) {
    report.real_note = o.real_frames_dir + " is not there: real frames skipped";
  } else {
    TLV_TRY(real_frames(o.real_frames_dir, probe, all, report.real_frames));
    if (report.real_frames == 0) report.real_note = o.real_frames_dir + " holds no RGB PNG/JPEG";
  }
  for (const PathTally& t : all) report.paths.push_back(summarise(t));
  return report;
}

std::string format_stability(const StabilityReport& r) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof(line),
                "stability of %s: %d simulated scenes, %lld real frames%s%s\n"
                "targets: cosine >= %.2f on every item, trusted heads agree on >= %.0f %%\n",
                r.model.c_str(), r.scenes, static_cast<long long>(r.real_frames),
                r.real_note.empty() ? "" : "; ", r.real_note.c_str(), kStabilityMinCosine,
                100 * kStabilityMinAgreement);
  out += line;
  for (const PathStability& p : r.paths) {
    std::snprintf(line, sizeof(line), "%-9s %-20s n %4lld  cosine min %.3f p5 %.3f median %.3f  ",
                  p.source.c_str(), p.path.c_str(), static_cast<long long>(p.n), p.cos_min,
                  p.cos_p05, p.cos_median);
    out += line;
    for (const HeadAgreement& h : p.heads) {
      std::snprintf(line, sizeof(line), "%s%s %.1f %%  ", h.head.c_str(), h.trusted ? "" : "*",
                    100 * h.rate());
      out += line;
    }
    out += p.meets_target() ? "ok" : "BELOW TARGET";
    if (p.cos_min < kStabilityMinCosine) out += " (worst: " + p.worst + ")";
    out += "\n";
  }
  out += "(* untrusted head: not held to the agreement target)\n";
  return out;
}

std::string stability_json(const StabilityReport& r) {
  nlohmann::ordered_json j;
  j["model"] = r.model;
  j["scenes"] = r.scenes;
  j["real_frames"] = r.real_frames;
  j["real_note"] = r.real_note;
  j["targets"] = {{"min_cosine", kStabilityMinCosine}, {"min_agreement", kStabilityMinAgreement}};
  j["meets_target"] = r.meets_target();
  for (const PathStability& p : r.paths) {
    nlohmann::ordered_json heads = nlohmann::ordered_json::array();
    for (const HeadAgreement& h : p.heads) {
      heads.push_back({{"head", h.head}, {"trusted", h.trusted}, {"same", h.same}, {"n", h.n}});
    }
    j["paths"].push_back({{"source", p.source},
                          {"path", p.path},
                          {"n", p.n},
                          {"cos_min", p.cos_min},
                          {"cos_p05", p.cos_p05},
                          {"cos_median", p.cos_median},
                          {"worst", p.worst},
                          {"heads", heads},
                          {"meets_target", p.meets_target()}});
  }
  return j.dump(2);
}

}  // namespace tlvlink::eval
