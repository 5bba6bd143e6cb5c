// Heads of the user's own from labelled frames (user_head.h).

#include "tlvlink/eval/user_head.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <set>

#include "put_head.h"
#include "tlvlink/capture/recording.h"
#include "tlvlink/capture/sensor_models.h"
#include "tlvlink/eval/labelled_frames.h"
#include "tlvlink/eval/trust.h"
#include "tlvlink/heads/head_math.h"
#include "tlvlink/image/frame_decoder.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/io/sensor_frame.h"
#include "tlvlink/quantize/model_copy.h"

namespace tlvlink::eval {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string percent(double v) {
  char b[16];
  std::snprintf(b, sizeof b, "%.1f", 100.0 * v);
  return b;
}

// Frames of camera recordings through the sensor's live view: the daemon's FrameDecoder on the
// recorded bytes, the same pixels tlvlinkd would hand the model.
class RecordedFrames {
 public:
  explicit RecordedFrames(std::string sensor) : sensor_(std::move(sensor)) {}

  Result<tools::SensorFrame> frame(const LabelledFrame& f) {
    auto it = open_.find(f.path);
    if (it == open_.end()) {
      TLV_ASSIGN_OR_RETURN(capture::RecordingReader reader, capture::RecordingReader::open(f.path));
      TLV_ASSIGN_OR_RETURN(const capture::SensorModel* model, sensor_of(reader, f.path));
      TLV_ASSIGN_OR_RETURN(
          image::FrameDecoder decoder,
          image::FrameDecoder::create(reader.summary().format.format, model->view));
      Open o{std::move(reader), std::move(decoder), model, {}, {}};
      o.bytes.resize(o.reader.summary().max_frame_bytes);
      o.rgb.resize(o.decoder.output_bytes());
      it = open_.emplace(f.path, std::move(o)).first;
    }
    Open& o = it->second;
    capture::RecordInfo info;
    TLV_ASSIGN_OR_RETURN(bool found, o.reader.record_at(f.record_offset, info));
    TLV_ENSURE(found, ErrorCode::kFormat, "%s: no record at offset %llu", f.path.c_str(),
               static_cast<unsigned long long>(f.record_offset));
    const std::span<uint8_t> bytes = std::span<uint8_t>(o.bytes).first(info.bytes);
    TLV_TRY(o.reader.read_frame(info, bytes, /*verify=*/true));
    TLV_TRY(o.decoder.decode(bytes, o.rgb, f.relative.c_str()));
    tools::SensorFrame out;
    out.sensor = std::string(o.model->name);
    out.view = image::Image{o.model->view.width, o.model->view.height, 3, o.rgb};
    return out;
  }

 private:
  struct Open {
    capture::RecordingReader reader;
    image::FrameDecoder decoder;
    const capture::SensorModel* model;
    std::vector<uint8_t> bytes, rgb;
  };
  // The named sensor, else the one sensor model whose camera streams what was recorded.
  Result<const capture::SensorModel*> sensor_of(const capture::RecordingReader& r,
                                                const std::string& path) const {
    if (!sensor_.empty()) {
      const capture::SensorModel* m = capture::find_sensor_model(sensor_);
      TLV_ENSURE(m != nullptr, ErrorCode::kInvalidArgument, "unknown sensor '%s' (known: %s)",
                 sensor_.c_str(), tools::known_sensor_names().c_str());
      return m;
    }
    const image::FrameFormat& f = r.summary().format.format;
    std::vector<const capture::SensorModel*> found;
    std::string names;
    for (const capture::SensorModel& m : capture::sensor_models()) {
      if (m.format == f.format && m.width == f.width && m.height == f.height) {
        found.push_back(&m);
        names += (names.empty() ? "" : ", ") + std::string(m.name);
      }
    }
    TLV_ENSURE(found.size() == 1, ErrorCode::kInvalidArgument,
               "%s: a recording of %s %dx%d is %s; name the sensor (--sensor)", path.c_str(),
               image::pixel_format_name(f.format), f.width, f.height,
               found.empty() ? "no known sensor's camera stream"
                             : ("the stream of several sensors (" + names + ")").c_str());
    return found[0];
  }

  std::string sensor_;
  std::map<std::string, Open> open_;
};

}  // namespace

Result<FrameFeatures> frame_features(const Model& model, const LabelledFrames& frames,
                                     const std::string& sensor, const EmbedderOptions& embedder) {
  const auto t0 = std::chrono::steady_clock::now();
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Embedder> e, Embedder::create(model, embedder));
  FrameFeatures f;
  f.dim = e->dim();
  const size_t pixel_dim = static_cast<size_t>(kBaselineWidth * kBaselineHeight * 3);
  f.embeddings.resize(frames.frames.size() * static_cast<size_t>(f.dim));
  f.pixels.resize(frames.frames.size() * pixel_dim);
  std::map<std::string, int64_t> views;
  RecordedFrames recorded(sensor);
  sim::RgbImage rgb;
  for (size_t i = 0; i < frames.frames.size(); ++i) {
    const LabelledFrame& lf = frames.frames[i];
    tools::SensorFrame sf;
    if (lf.record_offset > 0) {
      auto r = recorded.frame(lf);
      if (!r.ok()) return r.error();
      sf = std::move(r).value();
    } else {
      TLV_ASSIGN_OR_RETURN(sf, tools::sensor_frame_from_file(lf.path, sensor));
    }
    TLV_ENSURE(sf.view.channels == 3, ErrorCode::kFormat, "%s: %d channel(s); frames must be RGB",
               lf.path.c_str(), sf.view.channels);
    char size[48];
    std::snprintf(size, sizeof size, " %dx%d", sf.view.width,
                  sf.view.height);  // "a processed view 320x240"
    ++views[(sf.sensor.empty() ? "a processed view" : sf.sensor) + size];
    rgb.width = sf.view.width;
    rgb.height = sf.view.height;
    rgb.rgb = sf.view.pixels;
    TLV_TRY(
        e->embed(rgb, std::span<float>(f.embeddings)
                          .subspan(i * static_cast<size_t>(f.dim), static_cast<size_t>(f.dim))));
    TLV_ASSIGN_OR_RETURN(image::Image small, image::resize(sf.view.view(), kBaselineHeight,
                                                           kBaselineWidth, ResizeFilter::kArea));
    for (size_t k = 0; k < pixel_dim; ++k)
      f.pixels[i * pixel_dim + k] = static_cast<float>(small.pixels[k]) / 255.0f;
    f.labels.push_back(lf.label);
    f.groups.push_back(lf.group);
    f.sensors.push_back(sf.sensor);
  }
  for (const auto& [view, count] : views) {
    f.view_note += (f.view_note.empty() ? "" : ", ") + std::to_string(count) + " as " + view;
  }
  f.seconds = seconds_since(t0);
  return f;
}

Result<UserHeadFit> fit_user_head(const Model& model, const LabelledFrames& frames,
                                  const UserHeadOptions& o) {
  TLV_ENSURE(!o.head.empty(), ErrorCode::kInvalidArgument, "heads fit: the head needs a name");
  UserHeadFit fit;
  auto features = frame_features(model, frames, o.sensor, o.embedder);
  if (!features.ok()) return features.error();
  fit.features = std::move(features).value();
  const FrameFeatures& f = fit.features;
  const auto classes = static_cast<int32_t>(frames.classes.size());
  const GroupedRows head_rows{f.embeddings, f.dim, f.labels, classes, f.groups, frames.classes};
  const GroupedRows pixel_rows{
      f.pixels, kBaselineWidth * kBaselineHeight * 3, f.labels, classes, f.groups, frames.classes};
  const auto t0 = std::chrono::steady_clock::now();
  TLV_ASSIGN_OR_RETURN(fit.head_cv, cross_validate(head_rows, o.cv));
  TLV_ASSIGN_OR_RETURN(fit.baseline_cv, cross_validate(pixel_rows, o.cv));
  if (o.learning_curve) {
    TLV_ASSIGN_OR_RETURN(fit.head_curve, learning_curve(head_rows, o.cv));
    TLV_ASSIGN_OR_RETURN(fit.baseline_curve, learning_curve(pixel_rows, o.cv));
  }
  TLV_ASSIGN_OR_RETURN(FittedProbe p, fit_grouped(head_rows, o.cv));
  fit.fit_seconds = seconds_since(t0);
  fit.l2 = p.l2;

  quantize::LinearHeadSpec& h = fit.head;
  h.name = o.head;
  h.labels = frames.classes;
  h.weight = std::move(p.weight);
  h.bias = std::move(p.bias);
  const CvResult& cv = fit.head_cv;
  quantize::HeadTrustSpec& t = h.trust;
  t = cross_validated_trust(cv, fit.baseline_cv, kPixelBaseline);
  t.test_set = frames.dir + ": grouped " + std::to_string(cv.folds) + "-fold cross-validation, " +
               std::to_string(cv.n) + " frames, " + std::to_string(cv.groups) + " groups (" +
               grouping_name(frames.grouping) + ")";
  return fit;
}

Result<std::vector<std::byte>> model_with_user_head(const Model& model,
                                                    const quantize::LinearHeadSpec& head,
                                                    bool* replaced) {
  quantize::MetadataSpec meta = quantize::metadata_spec_from(model.metadata());
  const bool r = put_head(meta.linear_heads, head);
  if (replaced != nullptr) *replaced = r;
  return quantize::model_with_metadata(model, meta);
}

Result<HeadScore> score_model_head(const Model& model, const FrameFeatures& f,
                                   const LabelledFrames& frames, const std::string& head,
                                   uint64_t seed) {
  const Metadata& m = model.metadata();
  auto it = std::find_if(m.linear_heads.begin(), m.linear_heads.end(),
                         [&](const LinearHead& h) { return h.name == head; });
  if (it == m.linear_heads.end()) {
    std::string names;
    for (const LinearHead& h : m.linear_heads)
      names += (names.empty() ? "" : ", ") + std::string(h.name);
    return Error::make(ErrorCode::kInvalidArgument,
                       "the model has no linear head '%s' (it has: %s)", head.c_str(),
                       names.empty() ? "none" : names.c_str());
  }
  const LinearHead& h = *it;
  std::vector<int32_t> to_head(frames.classes.size(), -1);
  std::string labels;
  for (size_t c = 0; c < frames.classes.size(); ++c) {
    for (size_t k = 0; k < h.labels.size(); ++k)
      if (h.labels[k] == frames.classes[c]) to_head[c] = static_cast<int32_t>(k);
  }
  for (std::string_view l : h.labels) labels += (labels.empty() ? "" : ", ") + std::string(l);
  for (size_t c = 0; c < frames.classes.size(); ++c) {
    TLV_ENSURE(to_head[c] >= 0, ErrorCode::kInvalidArgument,
               "%s/%s: '%s' is not a label of head '%s' (its labels: %s); name the class folders "
               "after the head's labels",
               frames.dir.c_str(), frames.classes[c].c_str(), frames.classes[c].c_str(),
               head.c_str(), labels.c_str());
  }
  HeadScore s;
  s.head = head;
  s.n = static_cast<int64_t>(f.labels.size());
  s.predicted_counts.assign(h.labels.size(), 0);
  std::vector<float> logits(h.labels.size());
  std::vector<uint8_t> right(f.labels.size());
  std::set<std::string> groups(f.groups.begin(), f.groups.end());
  s.groups = static_cast<int64_t>(groups.size());
  for (size_t i = 0; i < f.labels.size(); ++i) {
    heads::linear_logits(h.weight, h.bias,
                         std::span<const float>(f.embeddings)
                             .subspan(i * static_cast<size_t>(f.dim), static_cast<size_t>(f.dim)),
                         logits);
    const int32_t answer = heads::argmax(logits);
    ++s.predicted_counts[static_cast<size_t>(answer)];
    right[i] = answer == to_head[static_cast<size_t>(f.labels[i])] ? 1 : 0;
  }
  if (s.n == 0) return s;
  const ClassMetrics metrics =
      class_metrics(f.labels, right, static_cast<int32_t>(frames.classes.size()));
  s.accuracy = metrics.accuracy;
  s.balanced_accuracy = metrics.balanced_accuracy;
  s.majority = metrics.majority;
  const Interval ci = group_bootstrap_interval(right, f.groups, seed);
  s.ci_low = ci.low;
  s.ci_high = ci.high;
  return s;
}

std::string format_user_head(const LabelledFrames& frames, const UserHeadFit& fit) {
  std::string out;
  char b[512];
  const CvResult& h = fit.head_cv;
  const CvResult& p = fit.baseline_cv;
  std::snprintf(
      b, sizeof b, "frames: %lld in %zu classes, %lld groups (grouping: %s); read as %s\n",
      static_cast<long long>(h.n), frames.classes.size(), static_cast<long long>(h.groups),
      grouping_name(frames.grouping), fit.features.view_note.c_str());
  out += b;
  for (size_t c = 0; c < frames.classes.size(); ++c) {
    std::snprintf(b, sizeof b, "  class %-16s %5lld frames  %4lld groups\n",
                  frames.classes[c].c_str(), static_cast<long long>(h.class_rows[c]),
                  static_cast<long long>(h.class_groups[c]));
    out += b;
  }
  if (frames.grouping == Grouping::kNone) {
    out +=
        "  warning: no groups (groups.tsv or <class>/<group>/ folders): frames of one object can "
        "be fitted and scored in different folds, so the accuracy below is optimistic\n";
  }
  std::snprintf(b, sizeof b,
                "grouped %d-fold cross-validation (L2 chosen inside each fitting fold):\n",
                h.folds);
  out += b;
  std::snprintf(b, sizeof b, "  %-30s accuracy %5s %% [%s, %s]  balanced %5s %%\n",
                "head (embeddings)", percent(h.accuracy).c_str(), percent(h.ci_low).c_str(),
                percent(h.ci_high).c_str(), percent(h.balanced_accuracy).c_str());
  out += b;
  std::snprintf(b, sizeof b, "  %-30s accuracy %5s %% [%s, %s]  balanced %5s %%\n",
                "baseline (32x24 pixels)", percent(p.accuracy).c_str(), percent(p.ci_low).c_str(),
                percent(p.ci_high).c_str(), percent(p.balanced_accuracy).c_str());
  out += b;
  std::snprintf(b, sizeof b, "  %-30s %5s %%\n", "majority class", percent(h.majority).c_str());
  out += b;
  for (size_t k = 0; k < fit.head_curve.size(); ++k) {
    if (k == 0)
      out +=
          "accuracy on the other groups, fitted on k groups per class (mean [min, max] over "
          "draws):\n";
    const CurvePoint& c = fit.head_curve[k];
    const CurvePoint& q = fit.baseline_curve[k];
    std::snprintf(b, sizeof b,
                  "  k=%-2d draws %3d  head %5s %% [%s, %s]  baseline %5s %% [%s, %s]  (%.0f "
                  "frames scored)\n",
                  c.groups_per_class, c.draws, percent(c.mean).c_str(), percent(c.min).c_str(),
                  percent(c.max).c_str(), percent(q.mean).c_str(), percent(q.min).c_str(),
                  percent(q.max).c_str(), c.mean_test_rows);
    out += b;
  }
  std::snprintf(b, sizeof b,
                "times: reading and embedding %.2f s, validation and fit %.2f s (L2 %g)\n",
                fit.features.seconds, fit.fit_seconds, fit.l2);
  out += b;
  return out;
}

}  // namespace tlvlink::eval
