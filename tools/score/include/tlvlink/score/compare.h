#pragma once
// Live vs offline on the same frames (issue 29's "live = offline" benchmark): each scenario is
// played twice by tlvlinkd, once from the cameras' raw output (the live image path) and once
// from the processed frames (`tlvlink sim scenario --offline`: exactly, or as the datasets
// store them), and both runs are scored against the truth frame by frame. Only frames both runs
// predicted are compared, so the difference is the image path's alone.
//
// Frames of one event show one object under one grip: the unit of resampling is the event
// (a cluster bootstrap over events, seeded), for the per-frame and per-event rates alike, and
// each scripted grasp for the grasps. Several scenarios pool their events.

#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/score/score.h"

namespace tlvlink::score {

struct RunFiles {
  std::string truth, live, offline;
};

// One rate measured both ways on the same items, with bootstrap 95 % intervals of each rate and
// of live minus offline.
struct PairedRate {
  Ratio live, offline;
  Interval live_ci, offline_ci;
  double difference_low = 0, difference_high = 0;  // live - offline, as fractions
  int64_t clusters = 0;                            // events (or grasps) resampled
  double difference() const { return live.rate() - offline.rate(); }
};

struct HeadComparison {
  std::string head;
  PairedRate frames, events;
};

// Issue 29's targets: per-frame head accuracy live within 2 points of offline, grasp accuracy
// within 3 points.
inline constexpr double kMaxFrameHeadGap = 0.02;
inline constexpr double kMaxGraspGap = 0.03;

struct LiveOfflineReport {
  int32_t runs = 0;
  int64_t events = 0;
  std::vector<HeadComparison> heads;
  PairedRate grasps;  // scripted grasps both runs predicted
  int32_t grasps_scripted = 0;
  int32_t live_grasps_missing = 0, offline_grasps_missing = 0;  // scripted, not predicted
  ScoreReport live, offline;  // each side's own score, pooled over the runs
  int32_t bootstrap_samples = 0;
  bool meets_target() const;
};

// Errors: unreadable or malformed files (naming file:line), runs without an offline file.
Result<LiveOfflineReport> compare_live_offline(const std::vector<RunFiles>& runs,
                                               const std::vector<std::string>& fingers,
                                               uint64_t bootstrap_seed = 1,
                                               int32_t bootstrap_samples = 2000);

// Sums `add` into `into` (counts; the majority rates are recomputed from the pooled labels).
void merge_scores(ScoreReport& into, const ScoreReport& add);

// What the --offline runs replayed: the exact processed frames (the targets apply), or the
// datasets' JPEG copy of them (information: what the datasets' codec alone moves; no targets).
enum class Reference { kExactFrames, kDatasetCopy };
const char* reference_name(Reference reference);  // "offline" / "dataset"

std::string format_live_offline(const LiveOfflineReport& report,
                                Reference reference = Reference::kExactFrames);
std::string format_live_offline_json(const LiveOfflineReport& report,
                                     Reference reference = Reference::kExactFrames);

}  // namespace tlvlink::score
