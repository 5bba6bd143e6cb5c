#include "tlvlink/pipeline/grasp_tracker.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace tlvlink::pipeline {
namespace {

using heads::Moment;

constexpr char finger_letter(int32_t f) { return f == 0 ? 'A' : 'B'; }
constexpr size_t index(Moment m) { return static_cast<size_t>(m); }

}  // namespace

Status validate(const GraspOptions& o) {
  constexpr int64_t kMax = 60'000'000'000;  // a minute: anything longer is a unit mistake
  for (const auto& [name, v] : {std::pair{"grasp.onset_window_ms", o.onset_window_ns},
                                {"grasp.settle_ms", o.settle_ns},
                                {"grasp.after_delay_ms", o.after_delay_ns},
                                {"grasp.idle_refresh_ms", o.idle_refresh_ns},
                                {"grasp.before_max_age_ms", o.before_max_age_ns},
                                {"grasp.pair_tolerance_ms", o.pair_tolerance_ns},
                                {"grasp.frame_timeout_ms", o.frame_timeout_ns}}) {
    TLV_ENSURE(v >= 0 && v <= kMax, ErrorCode::kInvalidArgument, "%s = %lld ms outside [0, 60000]",
               name, static_cast<long long>(v / 1'000'000));
  }
  TLV_ENSURE(o.frame_timeout_ns > 0, ErrorCode::kInvalidArgument,
             "grasp.frame_timeout_ms must be > 0");
  TLV_ENSURE(o.idle_refresh_ns < o.before_max_age_ns, ErrorCode::kInvalidArgument,
             "grasp.idle_refresh_ms (%lld) must be below grasp.before_max_age_ms (%lld): an "
             "open-gel frame must exist that is young enough",
             static_cast<long long>(o.idle_refresh_ns / 1'000'000),
             static_cast<long long>(o.before_max_age_ns / 1'000'000));
  return {};
}

const char* grasp_mode_name(GraspOptions::Mode m) {
  return m == GraspOptions::Mode::kCommanded ? "commanded" : "detected";
}

Result<GraspTracker> GraspTracker::create(std::span<const heads::GraspFeature> layout, int32_t dim,
                                          const GraspOptions& options, GraspImageShape images) {
  TLV_TRY(validate(options));
  TLV_ENSURE(!layout.empty() && layout.size() <= static_cast<size_t>(kMaxGraspFeatures),
             ErrorCode::kModelUnsupported, "grasp layout of %zu features (1..%d supported)",
             layout.size(), kMaxGraspFeatures);
  TLV_ENSURE(dim > 0, ErrorCode::kInvalidArgument, "grasp tracker: embedding dim %d", dim);
  GraspTracker t;
  t.layout_.assign(layout.begin(), layout.end());
  for (const heads::GraspFeature& f : t.layout_) {
    TLV_ENSURE(f.finger >= 0 && f.finger < heads::kFingers, ErrorCode::kModelUnsupported,
               "grasp layout names finger %d", f.finger);
  }
  t.dim_ = dim;
  t.options_ = options;
  for (const heads::GraspFeature& f : t.layout_) {
    t.offsets_.push_back(t.feature_values_);
    t.feature_values_ += static_cast<size_t>(heads::feature_values(f, dim));
    if (f.kind == heads::FeatureKind::kDifference) t.difference_[f.finger] = true;
  }
  if (heads::has_difference(t.layout_)) {
    TLV_ENSURE(images.height > 0 && images.width > 0 && images.channels > 0,
               ErrorCode::kInvalidArgument,
               "the grasp layout reads difference features: the tracker needs their image shape");
    auto stats = heads::GraspDifference::create(images.height, images.width, images.channels);
    if (!stats.ok()) return stats.error().with_context("grasp difference features");
    t.difference_stats_ = std::move(stats).value();
    t.image_values_ = t.difference_stats_.values();
    t.images_.assign(static_cast<size_t>(heads::kFingers) * 2 * t.image_values_, 0.0f);
    t.idle_images_.assign(static_cast<size_t>(heads::kFingers * kIdleHistory) * t.image_values_,
                          0.0f);
  }
  const size_t d = static_cast<size_t>(dim);
  t.embeddings_.assign(static_cast<size_t>(heads::kFingers * heads::kMoments) * d, 0.0f);
  t.idle_.assign(static_cast<size_t>(heads::kFingers * kIdleHistory) * d, 0.0f);
  t.finished_features_.assign(static_cast<size_t>(kMaxFinished) * t.feature_values_, 0.0f);
  return t;
}

bool GraspTracker::needed(int32_t finger, Moment moment) const {
  return heads::reads_frame(layout_, finger, moment);
}

bool GraspTracker::wants_image(int32_t finger) const {
  return finger >= 0 && finger < heads::kFingers && difference_[finger];
}

bool GraspTracker::image_needed(int32_t finger, Moment moment) const {
  return wants_image(finger) && (moment == Moment::kBefore || moment == Moment::kDuring);
}

float* GraspTracker::image_slot(int32_t finger, Moment moment) {
  const size_t slot = static_cast<size_t>(finger) * 2 + (moment == Moment::kDuring ? 1 : 0);
  return images_.data() + slot * image_values_;
}

// The time a moment's frames are taken from; -1 while it depends on what has not happened yet.
// ("before" is taken at the start from the open-gel frames, never waited for.)
int64_t GraspTracker::target(Moment m) const {
  if (phase_ != Phase::kWaiting) return -1;
  const bool commanded = options_.mode == GraspOptions::Mode::kCommanded;
  switch (m) {
    case Moment::kBefore: return -1;
    case Moment::kDuring: {
      const int64_t settled = start_ns_ + options_.settle_ns;
      return commanded && lifting_marked_ ? std::min(settled, lifting_ns_) : settled;
    }
    case Moment::kAfter: {
      if (commanded) return lifting_marked_ ? lifting_ns_ + options_.after_delay_ns : -1;
      // The later of the fingers' "during" frames (the "during" target when none is needed).
      int64_t latest = -1;
      bool any = false;
      for (int32_t f = 0; f < heads::kFingers; ++f) {
        if (!needed(f, Moment::kDuring)) continue;
        any = true;
        const Slot& s = slots_[f][index(Moment::kDuring)];
        if (!s.taken) return -1;
        latest = std::max(latest, s.t_ns);
      }
      return (any ? latest : target(Moment::kDuring)) + options_.after_delay_ns;
    }
  }
  return -1;
}

bool GraspTracker::wants(int32_t finger, int64_t t_ns) const {
  if (finger < 0 || finger >= heads::kFingers) return false;
  if (phase_ != Phase::kWaiting) {
    // Idle: keep an open-gel frame for the next grasp's "before" (the caller encodes it only
    // when the gate sees no contact; on_frame takes it only then).
    if (!needed(finger, Moment::kBefore) || contact_[finger]) return false;
    const Slot& idle = idle_slots_[finger][idle_newest_[finger]];
    return !idle.taken || t_ns - idle.t_ns >= options_.idle_refresh_ns;
  }
  for (Moment m : {Moment::kDuring, Moment::kAfter}) {
    if (!needed(finger, m) || slots_[finger][index(m)].taken) continue;
    const int64_t at = target(m);
    return at >= 0 && t_ns >= at;  // moments are taken in order: only the first open one counts
  }
  return false;
}

void GraspTracker::reset_grasp() {
  for (auto& finger : slots_)
    for (Slot& s : finger) s = Slot{};
  lifting_marked_ = false;
}

void GraspTracker::start(int64_t t_ns) {
  reset_grasp();
  phase_ = Phase::kWaiting;
  start_ns_ = t_ns;
  const size_t d = static_cast<size_t>(dim_);
  for (int32_t f = 0; f < heads::kFingers; ++f) {
    if (!needed(f, Moment::kBefore)) continue;
    // The newest open-gel frame; if it is later than the start (the finger's clock runs ahead
    // of the mark's), the one before it (written first, so kept only beside a newest one).
    const int32_t newest = idle_newest_[f];
    const int32_t older = 1 - newest;
    if (!idle_slots_[f][newest].taken) {
      fail(t_ns, "finger %c has no frame of its open gel before the grasp (its 'before' moment)",
           finger_letter(f));
      return;
    }
    const int32_t pick =
        idle_slots_[f][newest].t_ns > t_ns && idle_slots_[f][older].taken ? older : newest;
    const Slot& idle = idle_slots_[f][pick];
    if (t_ns - idle.t_ns > options_.before_max_age_ns) {
      fail(t_ns, "finger %c's last open-gel frame is %.1f s old (before_max_age %.1f s)",
           finger_letter(f), static_cast<double>(t_ns - idle.t_ns) * 1e-9,
           static_cast<double>(options_.before_max_age_ns) * 1e-9);
      return;
    }
    const size_t kept = static_cast<size_t>(f * kIdleHistory + pick);
    std::memcpy(embeddings_.data() +
                    (static_cast<size_t>(f) * heads::kMoments + index(Moment::kBefore)) * d,
                idle_.data() + kept * d, d * sizeof(float));
    if (image_needed(f, Moment::kBefore)) {
      std::memcpy(image_slot(f, Moment::kBefore), idle_images_.data() + kept * image_values_,
                  image_values_ * sizeof(float));
    }
    slots_[f][index(Moment::kBefore)] = idle;
  }
}

void GraspTracker::finish(bool computed, int64_t now_ns) {
  if (finished_count_ == kMaxFinished) {  // the oldest waiting record gives way
    finished_head_ = (finished_head_ + 1) % kMaxFinished;
    --finished_count_;
    ++finished_dropped_;
  }
  const int32_t at = (finished_head_ + finished_count_) % kMaxFinished;
  ++finished_count_;
  GraspPrediction& r = finished_[static_cast<size_t>(at)];
  r = GraspPrediction{};
  r.grasp_id = next_id_ - 1;
  r.computed = computed;
  r.started_ns = start_ns_;
  r.decided_ns = now_ns;
  if (!computed) std::memcpy(r.reason.data(), reason_.data(), r.reason.size());
  r.feature_count = static_cast<int32_t>(layout_.size());
  // The frames read, each once, in layout order (a difference reads "before" and "during").
  const auto add_frame = [&](int32_t finger, Moment m) {
    for (int32_t i = 0; i < r.frame_count; ++i) {
      const GraspFrameRef& ref = r.frames[static_cast<size_t>(i)];
      if (ref.finger == finger && ref.moment == static_cast<uint8_t>(m)) return;
    }
    const Slot& s = slots_[finger][index(m)];
    r.frames[static_cast<size_t>(r.frame_count++)] = {finger, static_cast<uint8_t>(m), s.sequence,
                                                      s.t_ns};
  };
  for (const heads::GraspFeature& f : layout_) {
    if (f.kind == heads::FeatureKind::kDifference) {
      add_frame(f.finger, Moment::kBefore);
      add_frame(f.finger, Moment::kDuring);
    } else {
      add_frame(f.finger, f.moment);
    }
  }
  const size_t d = static_cast<size_t>(dim_);
  float* features = finished_features_.data() + static_cast<size_t>(at) * feature_values_;
  for (size_t k = 0; computed && k < layout_.size(); ++k) {
    const heads::GraspFeature& f = layout_[k];
    if (f.kind == heads::FeatureKind::kDifference) {
      std::memcpy(features + offsets_[k],
                  differences_.data() + static_cast<size_t>(f.finger) * heads::kDifferenceFeatures,
                  heads::kDifferenceFeatures * sizeof(float));
    } else {
      const float* e = embeddings_.data() +
                       (static_cast<size_t>(f.finger) * heads::kMoments + index(f.moment)) * d;
      std::memcpy(features + offsets_[k], e, d * sizeof(float));
    }
  }
  phase_ = Phase::kFinished;
}

void GraspTracker::fail(int64_t now_ns, const char* format, ...) {
  va_list args;
  va_start(args, format);
  std::vsnprintf(reason_.data(), reason_.size(), format, args);
  va_end(args);
  finish(false, now_ns);
}

void GraspTracker::check_complete(int64_t now_ns) {
  if (phase_ != Phase::kWaiting) return;
  bool all = true;
  for (const heads::GraspFeature& f : layout_) {
    const Slot& s = slots_[f.finger][index(f.moment)];
    if (s.taken) continue;
    all = false;
    const int64_t at = target(f.moment);
    if (at >= 0 && now_ns - at > options_.frame_timeout_ns && last_frame_[f.finger] < at) {
      fail(now_ns, "finger %c sent no frame within %lld ms of its '%s' moment",
           finger_letter(f.finger), static_cast<long long>(options_.frame_timeout_ns / 1'000'000),
           heads::moment_name(f.moment));
      return;
    }
  }
  for (Moment m : {Moment::kDuring, Moment::kAfter}) {  // "before": an open gel, any time
    const Slot& a = slots_[0][index(m)];
    const Slot& b = slots_[1][index(m)];
    if (!a.taken || !b.taken || !needed(0, m) || !needed(1, m)) continue;
    const int64_t apart = std::llabs(a.t_ns - b.t_ns);
    if (apart > options_.pair_tolerance_ns) {
      fail(now_ns, "the fingers' '%s' frames are %.1f ms apart (tolerance %.1f ms)",
           heads::moment_name(m), static_cast<double>(apart) * 1e-6,
           static_cast<double>(options_.pair_tolerance_ns) * 1e-6);
      return;
    }
  }
  if (!all) return;
  for (int32_t f = 0; f < heads::kFingers; ++f) {
    if (!difference_[f]) continue;
    const std::span<float> out(
        differences_.data() + static_cast<size_t>(f) * heads::kDifferenceFeatures,
        heads::kDifferenceFeatures);
    const Status st = difference_stats_.compute(
        std::span<const float>(image_slot(f, Moment::kBefore), image_values_),
        std::span<const float>(image_slot(f, Moment::kDuring), image_values_), out);
    if (!st.ok()) {
      fail(now_ns, "finger %c: %s", finger_letter(f), st.error().message());
      return;
    }
  }
  finish(true, now_ns);
}

void GraspTracker::on_frame(int32_t finger, uint64_t sequence, int64_t t_ns, bool contact,
                            std::span<const float> embedding, std::span<const float> image) {
  if (finger < 0 || finger >= heads::kFingers) return;
  const size_t d = static_cast<size_t>(dim_);
  last_frame_[finger] = t_ns;
  if (contact && !contact_[finger]) onset_[finger] = t_ns;
  if (!contact) onset_[finger] = -1;
  contact_[finger] = contact;
  // A finger whose difference is read keeps only open-gel frames that come with their image.
  const bool has_image = image.size() == image_values_ && image_values_ > 0;
  if (!contact && phase_ != Phase::kWaiting && embedding.size() == d &&
      (!difference_[finger] || has_image)) {
    int32_t& newest = idle_newest_[finger];
    if (idle_slots_[finger][newest].taken) newest = 1 - newest;  // the older one gives way
    const size_t kept = static_cast<size_t>(finger * kIdleHistory + newest);
    std::memcpy(idle_.data() + kept * d, embedding.data(), d * sizeof(float));
    if (difference_[finger]) {
      std::memcpy(idle_images_.data() + kept * image_values_, image.data(),
                  image_values_ * sizeof(float));
    }
    idle_slots_[finger][newest] = {true, sequence, t_ns};
  }
  const bool detected = options_.mode == GraspOptions::Mode::kDetected;
  if (phase_ == Phase::kFinished) {
    // Detected: a new grasp needs both fingers to let go first. Commanded: the next mark.
    if (!detected || (!contact_[0] && !contact_[1])) phase_ = Phase::kIdle;
    return;
  }
  if (phase_ == Phase::kIdle) {
    if (detected && contact_[0] && contact_[1] &&
        std::llabs(onset_[0] - onset_[1]) <= options_.onset_window_ns) {
      ++next_id_;
      start(std::max(onset_[0], onset_[1]));
    }
    if (phase_ != Phase::kWaiting) return;
  }
  for (Moment m : {Moment::kDuring, Moment::kAfter}) {
    if (!needed(finger, m)) continue;
    Slot& s = slots_[finger][index(m)];
    if (s.taken) continue;
    if (detected && !contact) {
      fail(t_ns, "finger %c let go before its '%s' frame", finger_letter(finger),
           heads::moment_name(m));
      return;
    }
    const int64_t at = target(m);
    if (at < 0 || t_ns < at) break;  // moments are taken in order, one per frame
    if (embedding.size() != d) {
      fail(t_ns, "finger %c frame %llu (its '%s' frame) was not encoded", finger_letter(finger),
           static_cast<unsigned long long>(sequence), heads::moment_name(m));
      return;
    }
    if (image_needed(finger, m)) {
      if (!has_image) {
        fail(t_ns,
             "finger %c frame %llu (its '%s' frame) came without the image its difference "
             "features need",
             finger_letter(finger), static_cast<unsigned long long>(sequence),
             heads::moment_name(m));
        return;
      }
      std::memcpy(image_slot(finger, m), image.data(), image_values_ * sizeof(float));
    }
    std::memcpy(embeddings_.data() + (static_cast<size_t>(finger) * heads::kMoments + index(m)) * d,
                embedding.data(), d * sizeof(float));
    s = {true, sequence, t_ns};
    break;
  }
  check_complete(t_ns);
}

void GraspTracker::tick(int64_t now_ns) { check_complete(now_ns); }

bool GraspTracker::mark_closed(int64_t t_ns) {
  if (options_.mode != GraspOptions::Mode::kCommanded) return false;
  if (phase_ == Phase::kWaiting) fail(t_ns, "superseded by a new 'closed' mark");
  ++next_id_;
  start(t_ns);
  return true;
}

bool GraspTracker::mark_lifting(int64_t t_ns) {
  if (options_.mode != GraspOptions::Mode::kCommanded) return false;
  // A grasp already decided at "during" (the usual case) has no use for the lift.
  if (phase_ != Phase::kWaiting) return true;
  lifting_marked_ = true;
  lifting_ns_ = t_ns;
  return true;
}

bool GraspTracker::take_finished(GraspPrediction& out,
                                 std::span<const float> (&features)[kMaxGraspFeatures]) {
  if (finished_count_ == 0) return false;
  const int32_t at = finished_head_;
  finished_head_ = (finished_head_ + 1) % kMaxFinished;
  --finished_count_;
  out = finished_[static_cast<size_t>(at)];
  const float* base = finished_features_.data() + static_cast<size_t>(at) * feature_values_;
  for (size_t k = 0; k < static_cast<size_t>(kMaxGraspFeatures); ++k) {
    features[k] =
        out.computed && k < layout_.size()
            ? std::span<const float>(base + offsets_[k],
                                     static_cast<size_t>(heads::feature_values(layout_[k], dim_)))
            : std::span<const float>();
  }
  return true;
}

}  // namespace tlvlink::pipeline
