// extract_embeddings: streams the touch and grasp loaders through an Embedder.

#include <algorithm>
#include <chrono>

#include "data_paths.h"
#include "frame_pool.h"
#include "tlvlink/datasets/feel.h"
#include "tlvlink/datasets/touch100k.h"
#include "tlvlink/datasets/touch_and_go.h"
#include "tlvlink/eval/embeddings.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/io/progress.h"

namespace tlvlink::eval {
namespace {

using internal::join;

// One touch sample and its rows: the frame as loaded, then (train split only) its re-encodings
// and its live view, each a row viewing the first. Embedded by a pool worker, committed in order.
struct TouchItem {
  sim::TouchSample sample;
  std::string key;
  bool test = false, has_labels = false;
  bool live_view = false;     // false for a frame that already took its sensor's live path
  std::vector<float> values;  // [rows, dim]
  sim::RgbImage live_frame;   // the worker's live view of `sample`
};

struct TouchSink {
  TouchSink(internal::FramePool& workers, TouchEmbeddings& rows_out, tools::Progress& bar,
            int64_t per_split_cap, std::vector<int32_t> jpeg_qualities, bool live_path)
      : pool(workers),
        out(rows_out),
        progress(bar),
        cap(per_split_cap),
        train_jpeg(std::move(jpeg_qualities)),
        train_live(live_path),
        live(static_cast<size_t>(workers.workers())),
        batches(
            workers, 64, [this](TouchItem& i, int32_t w) { return embed_rows(i, w); },
            [this](TouchItem& i) { return commit(i); }) {}

  internal::FramePool& pool;
  TouchEmbeddings& out;
  tools::Progress& progress;
  int64_t cap = 0;  // per split, 0 = none
  int64_t taken[2] = {0, 0};
  std::vector<int32_t> train_jpeg;        // EvalData::train_jpeg_qualities
  bool train_live = false;                // EvalData::train_live_path
  std::vector<internal::LivePaths> live;  // one per worker
  internal::BatchPipeline<TouchItem> batches;

  bool adds_views() const { return !train_jpeg.empty() || train_live; }

  bool full(bool test) const { return cap > 0 && taken[test ? 1 : 0] >= cap; }

  // The sample the loader fills next; add() takes it (or leaves it when its split is full).
  sim::TouchSample& slot() { return batches.slot().sample; }

  Status add(const std::string& key, bool test, bool has_labels, bool live_view = true) {
    if (full(test)) return {};
    TouchItem& item = batches.slot();
    item.key = key;
    item.test = test;
    item.has_labels = has_labels;
    item.live_view = live_view;
    ++taken[test ? 1 : 0];
    return batches.push();
  }

  Status finish() { return batches.finish(); }

  size_t rows(const TouchItem& i) const {
    if (i.test) return 1;
    return 1 + train_jpeg.size() + (train_live && i.live_view ? 1 : 0);
  }
  std::string row_key(const TouchItem& i, size_t r) const {
    if (r == 0) return i.key;
    if (r <= train_jpeg.size()) return i.key + "#jpeg-q" + std::to_string(train_jpeg[r - 1]);
    return i.key + "#live";
  }

  // On worker `w`: every row of the item (the frame, its JPEG re-encodings, its live view: the
  // camera's raw output and the board's decoder, what tlvlinkd reads).
  Status embed_rows(TouchItem& i, int32_t w) {
    const size_t d = static_cast<size_t>(out.dim), n = rows(i);
    i.values.resize(n * d);
    Embedder& embedder = pool.embedder(w);
    const sim::TouchSample& s = i.sample;
    for (size_t r = 0; r < n; ++r) {
      const std::span<float> row(i.values.data() + r * d, d);
      Status st;
      if (r == 0) {
        st = embedder.embed(s.touch, row);
      } else if (r <= train_jpeg.size()) {
        TLV_ASSIGN_OR_RETURN(const sim::RgbImage j,
                             internal::jpeg_path(s.touch, train_jpeg[r - 1]));
        st = embedder.embed(j, row);
      } else {
        TLV_ENSURE(!s.sensor.empty(), ErrorCode::kInvalidArgument,
                   "--train-live: touch sample '%s' does not record its sensor (a simulated set "
                   "does; real data has no live path to replay)",
                   i.key.c_str());
        i.live_frame = s.touch;
        if (Status l = live[static_cast<size_t>(w)].apply(s.sensor, i.live_frame.rgb); !l.ok())
          return l.error().with_context("--train-live: sample '%s'", i.key.c_str());
        st = embedder.embed(i.live_frame, row);
      }
      if (!st.ok()) return st.error().with_context("touch sample '%s'", row_key(i, r).c_str());
    }
    return {};
  }

  // On the caller's thread, in order: the item's rows with the sample's labels.
  Status commit(const TouchItem& i) {
    const size_t d = static_cast<size_t>(out.dim);
    const auto original = static_cast<int64_t>(out.size());
    const sim::TouchSample& s = i.sample;
    for (size_t r = 0; r < rows(i); ++r) {
      out.values.insert(out.values.end(), i.values.begin() + static_cast<std::ptrdiff_t>(r * d),
                        i.values.begin() + static_cast<std::ptrdiff_t>((r + 1) * d));
      out.material.push_back(i.has_labels ? s.material.class_id : -1);
      out.hard.push_back(i.has_labels ? (s.material.hard ? 1 : 0) : -1);
      out.rough.push_back(i.has_labels ? s.material.rough : -1);
      out.group.push_back(s.session);
      out.is_test.push_back(i.test ? 1 : 0);
      out.keys.push_back(row_key(i, r));
      if (adds_views()) out.view_of.push_back(r == 0 ? -1 : original);
      out.hidden_material.push_back(s.material);
      if (!i.has_labels) out.hidden_material.back().class_id = -1;
      out.hidden_contact.push_back(s.contact);
    }
    progress.add();
    return {};
  }
};

Status run_touch100k(const EvalData& data, TouchSink& sink) {
  // The recorded split lives in the simulator's sidecar; a set without one is split by hash.
  const std::optional<datasets::HashSplit> hash =
      internal::split_to_apply(data, data.touch_dir, datasets::DatasetFormat::kTouch100k);
  datasets::Touch100kLoaderOptions o;
  o.load_vision = o.require_vision = false;
  o.scale_denominator = data.scale_denominator;
  TLV_ASSIGN_OR_RETURN(auto loader, datasets::open_touch100k(data.touch_dir, o));
  if (data.problems != nullptr) loader->report().on_problem = data.problems->callback();
  for (;;) {
    sim::TouchSample& s = sink.slot();
    TLV_ASSIGN_OR_RETURN(const bool more, loader->next(s));
    if (!more || (sink.full(false) && sink.full(true))) break;
    const std::string& key = loader->key();
    bool test = false;
    if (hash) {
      test = datasets::hash_split_is_test(s.session, *hash);
    } else {
      const datasets::Split recorded = loader->recorded_split();
      TLV_ENSURE(recorded != datasets::Split::kAll, ErrorCode::kFormat,
                 "%s: sample '%s' has no recorded split in %s (or evaluate with a hash split)",
                 data.touch_dir.c_str(), key.c_str(), datasets::kTouch100kSidecar);
      test = recorded == datasets::Split::kTest;
    }
    // Without the simulator's sidecar Touch100k has no labels (class_id stays -1).
    TLV_TRY(sink.add(key, test, s.material.class_id >= 0));
  }
  sink.out.split.source = internal::split_source(hash);
  sink.out.format = "touch100k";
  sink.out.load_summary = loader->report().summary();
  return {};
}

Status run_tag(const EvalData& data, TouchSink& sink) {
  const std::optional<datasets::HashSplit> hash =
      internal::split_to_apply(data, data.touch_dir, datasets::DatasetFormat::kTouchAndGo);
  std::string summary;
  for (const bool test : {false, true}) {
    datasets::TagLoaderOptions o;
    o.load_vision = o.require_vision = false;
    o.scale_denominator = data.scale_denominator;
    o.split = test ? datasets::Split::kTest : datasets::Split::kTrain;
    o.resplit = hash;
    TLV_ASSIGN_OR_RETURN(auto loader, datasets::open_touch_and_go(data.touch_dir, o));
    if (data.problems != nullptr) loader->report().on_problem = data.problems->callback();
    for (;;) {
      sim::TouchSample& s = sink.slot();
      TLV_ASSIGN_OR_RETURN(const bool more, loader->next(s));
      if (!more || sink.full(test)) break;
      TLV_TRY(sink.add(loader->key(), test, s.material.class_id >= 0));
    }
    summary += std::string(summary.empty() ? "" : "; ") + (test ? "test: " : "train: ") +
               loader->report().summary();
  }
  sink.out.split.source = internal::split_source(hash);
  sink.out.format = "touch_and_go";
  sink.out.load_summary = summary;
  return {};
}

// One split of a grasp set (Feel HDF5 or repacked), frames only, as the data asks them decoded.
Result<std::unique_ptr<datasets::GraspEpisodeLoader>> open_grasp_split(
    const EvalData& data, const std::string& dir, GraspFormat format, datasets::Split split,
    const std::optional<datasets::HashSplit>& resplit) {
  datasets::FeelLoaderOptions o;
  o.load_vision = o.require_vision = false;
  o.scale_denominator = data.scale_denominator;
  o.split = split;
  o.resplit = resplit;
  o.gelsight_quarter_turns = data.gelsight_quarter_turns;
  return format == GraspFormat::kFeelHdf5 ? datasets::open_feel(dir, o)
                                          : datasets::open_feel_repacked(dir, o);
}

// EvalData::touch_from_grasps: each TRAINING grasp's "during" frame of either finger, as a touch
// train row labelled with the grasped object's material (its session: the object).
Status run_grasp_touches(const EvalData& data, TouchSink& sink) {
  const std::string& dir = data.touch_from_grasps_dir;
  Result<GraspFormat> detected = internal::detect_grasp_format(dir, GraspFormat::kAuto);
  if (!detected.ok()) return detected.error().with_context("--touch-from-grasps");
  auto loader =
      open_grasp_split(data, dir, *detected, datasets::Split::kTrain,
                       internal::split_to_apply(data, dir, internal::dataset_format(*detected)));
  if (!loader.ok()) return loader.error().with_context("--touch-from-grasps %s", dir.c_str());
  sim::GraspEpisode e;
  sim::TouchSample s;
  int64_t labelled = 0;
  for (;;) {
    TLV_ASSIGN_OR_RETURN(const bool more, (*loader)->next(e));
    if (!more || sink.full(false)) break;
    if (e.material.class_id < 0) continue;  // a real Feel episode: no material recorded
    ++labelled;
    s.session = "grasp:" + e.object_name;
    s.object_id = e.object_id;
    s.sensor = e.sensor;
    s.material = e.material;
    for (int32_t f = 0; f < heads::kFingers; ++f) {
      s.sensor_instance = e.sensor_instance[f];
      sim::TouchSample& t = sink.slot();  // every field from `s`: a slot keeps its last sample's
      t = s;
      t.touch = e.frames[f][static_cast<int>(heads::Moment::kDuring)];
      TLV_TRY(sink.add((*loader)->key() + (f == 0 ? "#A" : "#B"), /*test=*/false,
                       /*has_labels=*/true, /*live_view=*/!e.live_path));
    }
  }
  TLV_ENSURE(labelled > 0, ErrorCode::kFormat,
             "--touch-from-grasps %s: no training episode records its object's material (a "
             "simulated Feel set does)",
             dir.c_str());
  return {};
}

Result<TouchEmbeddings> extract_touch(internal::FramePool& pool, const EvalData& data,
                                      const EmbedderOptions& options) {
  TLV_ASSIGN_OR_RETURN(const TouchFormat format,
                       internal::detect_touch_format(data.touch_dir, data.touch_format));
  TouchEmbeddings out;
  out.dim = pool.embedder(0).dim();
  int64_t total = internal::expected_touch_items(data.touch_dir, format);
  if (data.max_touch_samples > 0) total = std::min(total, 2 * data.max_touch_samples);
  tools::Progress progress(
      "embedding touch frames", total, stderr,
      options.progress ? tools::ProgressMode::kAuto : tools::ProgressMode::kQuiet);
  TouchSink sink(pool, out, progress, data.max_touch_samples, data.train_jpeg_qualities,
                 data.train_live_path);
  if (format == TouchFormat::kTouch100k) {
    TLV_TRY(run_touch100k(data, sink));
  } else {
    TLV_TRY(run_tag(data, sink));
  }
  if (!data.touch_from_grasps_dir.empty()) TLV_TRY(run_grasp_touches(data, sink));
  TLV_TRY(sink.finish());
  if (options.progress) progress.finish();
  internal::fill_split_counts(out.split, out.group, out.is_test);
  TLV_ENSURE(out.size() > 0, ErrorCode::kFormat, "%s: no touch sample could be loaded (%s)",
             data.touch_dir.c_str(), out.load_summary.c_str());
  bool labelled = false;
  for (size_t i = 0; i < out.size() && !labelled; ++i)
    labelled = out.material[i] >= 0 || out.hard[i] >= 0 || out.rough[i] >= 0;
  TLV_ENSURE(labelled, ErrorCode::kFormat,
             "%s: %zu samples but no material, hard/soft or rough/smooth label (a Touch100k set "
             "carries labels only in the simulator's %s sidecar)",
             data.touch_dir.c_str(), out.size(), datasets::kTouch100kSidecar);
  return out;
}

// Each finger's difference features of an episode (grasp_difference.h), on the model's crop and
// resize in DN, as the daemon's grasp tracker computes them.
class EpisodeDifference {
 public:
  static Result<std::optional<EpisodeDifference>> create(const InputSpec& input) {
    if (input.channels != 3) return std::optional<EpisodeDifference>();  // no differences
    EpisodeDifference e;
    e.spec_ = heads::difference_input_spec(input);
    TLV_ASSIGN_OR_RETURN(e.stats_,
                         heads::GraspDifference::create(input.height, input.width, input.channels));
    return std::optional<EpisodeDifference>(std::move(e));
  }
  Status compute(const sim::GraspEpisode& e, std::span<float> out) {
    constexpr auto n = static_cast<size_t>(heads::kDifferenceFeatures);
    for (int32_t f = 0; f < heads::kFingers; ++f) {
      const sim::RgbImage& b = e.frames[f][static_cast<int>(heads::Moment::kBefore)];
      const sim::RgbImage& d = e.frames[f][static_cast<int>(heads::Moment::kDuring)];
      TLV_ASSIGN_OR_RETURN(
          const std::vector<float> before,
          image::preprocess(image::ImageView{b.rgb.data(), b.width, b.height, 3, 0}, spec_));
      TLV_ASSIGN_OR_RETURN(
          const std::vector<float> during,
          image::preprocess(image::ImageView{d.rgb.data(), d.width, d.height, 3, 0}, spec_));
      TLV_TRY(stats_.compute(before, during, out.subspan(static_cast<size_t>(f) * n, n)));
    }
    return {};
  }

 private:
  InputSpec spec_;
  heads::GraspDifference stats_;
};

// One grasp episode: its frames' embeddings and each finger's difference statistics, computed by
// a pool worker, committed in order.
struct GraspItem {
  sim::GraspEpisode e;
  std::string key;
  bool test = false;
  std::vector<float> values;      // [kGraspFrames, dim]
  std::vector<float> difference;  // [kFingers, kDifferenceFeatures], empty without differences
};

Result<GraspEmbeddings> extract_grasp(internal::FramePool& pool, const EvalData& data,
                                      const EmbedderOptions& options) {
  // One per worker (each keeps its own buffers).
  std::vector<std::optional<EpisodeDifference>> differences;
  for (int32_t w = 0; w < pool.workers(); ++w) {
    TLV_ASSIGN_OR_RETURN(std::optional<EpisodeDifference> difference,
                         EpisodeDifference::create(pool.embedder(w).model().metadata().input));
    differences.push_back(std::move(difference));
  }
  TLV_ASSIGN_OR_RETURN(const GraspFormat format,
                       internal::detect_grasp_format(data.grasp_dir, data.grasp_format));
  const std::optional<datasets::HashSplit> hash =
      internal::split_to_apply(data, data.grasp_dir, internal::dataset_format(format));
  GraspEmbeddings out;
  out.dim = pool.embedder(0).dim();
  out.format = format == GraspFormat::kFeelHdf5 ? "feel_hdf5" : "feel_repacked";
  out.generator_json = internal::generator_json(data.grasp_dir);
  const size_t d = static_cast<size_t>(out.dim);
  constexpr auto n = static_cast<size_t>(heads::kFingers * heads::kDifferenceFeatures);
  int64_t total = internal::expected_grasp_items(data.grasp_dir, format);
  if (data.max_grasp_episodes > 0) total = std::min(total, 2 * data.max_grasp_episodes);
  tools::Progress progress(
      "embedding grasp episodes", total, stderr,
      options.progress ? tools::ProgressMode::kAuto : tools::ProgressMode::kQuiet);
  auto embed = [&](GraspItem& g, int32_t w) -> Status {
    g.values.resize(d * kGraspFrames);
    for (int32_t f = 0; f < heads::kFingers; ++f) {
      for (int32_t m = 0; m < heads::kMoments; ++m) {
        std::span<float> row(g.values.data() + static_cast<size_t>(f * heads::kMoments + m) * d, d);
        if (Status st = pool.embedder(w).embed(g.e.frames[f][m], row); !st.ok()) {
          return st.error().with_context("grasp episode '%s' finger %d moment %d", g.key.c_str(), f,
                                         m);
        }
      }
    }
    std::optional<EpisodeDifference>& difference = differences[static_cast<size_t>(w)];
    g.difference.resize(difference ? n : 0);
    if (difference) {
      if (Status st = difference->compute(g.e, g.difference); !st.ok())
        return st.error().with_context("grasp episode '%s'", g.key.c_str());
    }
    return {};
  };
  auto commit = [&](GraspItem& g) -> Status {
    const sim::GraspEpisode& e = g.e;
    out.values.insert(out.values.end(), g.values.begin(), g.values.end());
    out.difference.insert(out.difference.end(), g.difference.begin(), g.difference.end());
    out.label.push_back(e.is_gripping ? 1 : 0);
    out.live_path.push_back(e.live_path ? 1 : 0);
    out.hidden_variables.push_back(e.variables);
    out.hidden_material.push_back(e.material);
    out.hidden_during.push_back({e.states[0][static_cast<int>(heads::Moment::kDuring)],
                                 e.states[1][static_cast<int>(heads::Moment::kDuring)]});
    out.group.push_back(e.object_name);
    out.sensor.push_back(e.sensor);
    out.is_test.push_back(g.test ? 1 : 0);
    out.keys.push_back(g.key);
    progress.add();
    return {};
  };
  internal::BatchPipeline<GraspItem> batches(pool, 32, embed, commit);
  std::string summary;
  for (const bool test : {false, true}) {
    auto loader = open_grasp_split(data, data.grasp_dir, format,
                                   test ? datasets::Split::kTest : datasets::Split::kTrain, hash);
    if (!loader.ok()) return loader.error();
    if (data.problems != nullptr) (*loader)->report().on_problem = data.problems->callback();
    int64_t taken = 0;
    for (;;) {
      GraspItem& g = batches.slot();
      TLV_ASSIGN_OR_RETURN(const bool more, (*loader)->next(g.e));
      if (!more || (data.max_grasp_episodes > 0 && taken >= data.max_grasp_episodes)) break;
      g.key = (*loader)->key();
      g.test = test;
      ++taken;
      TLV_TRY(batches.push());
    }
    summary += std::string(summary.empty() ? "" : "; ") + (test ? "test: " : "train: ") +
               (*loader)->report().summary();
  }
  TLV_TRY(batches.finish());
  if (options.progress) progress.finish();
  out.split.source = internal::split_source(hash);
  out.load_summary = summary;
  internal::fill_split_counts(out.split, out.group, out.is_test);
  TLV_ENSURE(out.size() > 0, ErrorCode::kFormat, "%s: no grasp episode could be loaded (%s)",
             data.grasp_dir.c_str(), summary.c_str());
  return out;
}

}  // namespace

Result<EmbeddingSet> extract_embeddings(const Model& model, const EvalData& data,
                                        const EmbedderOptions& options) {
  TLV_ENSURE(!data.touch_dir.empty() || !data.grasp_dir.empty(), ErrorCode::kInvalidArgument,
             "no dataset given (a touch dir and/or a grasp dir)");
  TLV_ENSURE(data.max_touch_samples >= 0 && data.max_grasp_episodes >= 0,
             ErrorCode::kInvalidArgument, "sample caps must be >= 0 (0 = all)");
  for (const int32_t q : data.train_jpeg_qualities) {
    TLV_ENSURE(q >= 1 && q <= 100, ErrorCode::kInvalidArgument,
               "--train-jpeg %d: a JPEG quality is 1..100", q);
  }
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<internal::FramePool> pool,
                       internal::FramePool::create(model, options));
  const auto t0 = std::chrono::steady_clock::now();
  EmbeddingSet set;
  if (!data.touch_dir.empty()) {
    TLV_ASSIGN_OR_RETURN(TouchEmbeddings t, extract_touch(*pool, data, options));
    set.frames += static_cast<int64_t>(t.size());
    set.touch = std::move(t);
  }
  if (!data.grasp_dir.empty()) {
    TLV_ASSIGN_OR_RETURN(GraspEmbeddings g, extract_grasp(*pool, data, options));
    set.frames += static_cast<int64_t>(g.size()) * kGraspFrames;
    set.grasp = std::move(g);
  }
  set.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return set;
}

}  // namespace tlvlink::eval
