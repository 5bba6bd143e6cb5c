#pragma once
// Scores a live run: tlvlinkd's JSON-lines output against the ground truth of the scenario it
// played (`tlvlink sim scenario`: truth.jsonl). Frames are matched by sensor and sequence
// number (a looped replay's sequences continue: they are taken modulo the scenario's length).
//
//   contact gating   per frame: the gate's decision against the renderer's contact (a missed
//                    contact is worse than a wasted inference), and the encoder runs it saved
//   per-frame heads  in contact (the renderer's), each head's label against the event's material
//                    labels: per frame, and per event at its last predicted frame (the smoothed
//                    answer). Labels the daemon gave frames the renderer shows without contact
//                    (the gate's false contacts inside an event) are counted apart, not scored.
//                    Frames of one event are one object under one grip, so they are not
//                    independent: the event and grasp figures carry a 95 % interval (Wilson),
//                    the per-frame ones do not (read them with the event count). A press head
//                    ("hard_soft_press": one answer per contact, from its fourth frame on) is
//                    scored against the label it is named after; per event, its answer at the
//                    event's last frame is the one over the whole press.
//   grasps           each grasp record matched to the scripted grasp its "during" frame falls
//                    in: computed or not (with the reason), success predicted against the label

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::score {

// A contact frame whose image differs from the open gel by less than this (the largest 32x24
// block mean, DN; the scenario records it as signal_dn) shows nothing a camera can tell from
// noise: two frames of the same open gel already differ by up to ~3.2 DN there (DIGIT's
// noise, over 12,500 open frames of a scenario; tests/sim/scenario checks every open frame of
// its own stays below this), and a smooth flat face
// filling the gel leaves every surface normal as it was (0.4 DN without noise). The contact
// gate cannot be asked to see it; such frames (and events made only of them) are counted
// apart, and a controller's "closed" mark is what starts a grasp on them.
inline constexpr double kInvisibleSignalDn = 3.5;

struct Ratio {
  int64_t hits = 0, total = 0;
  double rate() const {
    return total > 0 ? static_cast<double>(hits) / static_cast<double>(total) : 0.0;
  }
};

// The Wilson score interval of a binomial rate at z = 1.96 (95 %): {0, 1} for an empty ratio.
struct Interval {
  double low = 0, high = 1;
};
Interval wilson95(const Ratio& r);

struct HeadScore {
  std::string head;             // "material", "hard_soft", "rough_smooth", "hard_soft_press"
  Ratio frames;                 // frames in contact with a prediction and a defined label
  int64_t without_contact = 0;  // labelled frames of an event the renderer shows without contact
  Ratio events;                 // the last prediction of each event
  double majority = 0;          // accuracy of always answering the events' most common label
  std::map<std::string, int64_t> event_labels;  // the scored events' true labels, counted
};

struct ScoreReport {
  int64_t truth_frames = 0;      // per finger, in the scenario
  int64_t frames = 0;            // daemon frame records matched to the truth
  int64_t unmatched_frames = 0;  // frame records of sensors not named in `fingers`
  int64_t calibrating = 0;       // frames while the gate learnt its reference (not scored)
  // Contact gating.
  int64_t truth_contact = 0;      // matched frames the renderer shows in contact
  int64_t missed_contact = 0;     // of those, gated as no contact (false negatives)
  int64_t missed_light = 0;       // of the misses, under 1 N (ramp ends)
  int64_t false_contact = 0;      // gated as contact with the gel open
  int64_t invisible_contact = 0;  // in contact by the renderer, signal < kInvisibleSignalDn (not
                                  // in truth_contact; of them, gated as contact below)
  int64_t invisible_seen = 0;
  int64_t invisible_events = 0;  // events whose every contact frame is invisible
  int64_t encoded = 0;           // frames the encoder ran on
  Ratio contact_events;          // events whose contact the gate saw at least once
  // Per event kind ("grasp", "press"): frames in contact the gate missed (hits = missed).
  std::map<std::string, Ratio> missed_by_kind;
  // Heads.
  std::vector<HeadScore> heads;
  // Grasps.
  int32_t truth_grasps = 0;     // scripted grasp events in the frames that were played
  int32_t grasp_records = 0;    // grasp records in the output
  int32_t grasps_computed = 0;  // computed, matched to a scripted grasp
  int32_t grasps_not_computed = 0;
  int32_t grasps_unmatched = 0;       // records whose frames fall outside any scripted grasp
  Ratio grasp_accuracy;               // predicted success == label, over computed and matched
  double grasp_majority = 0;          // always answering the scripted grasps' majority label
  int32_t truth_grasp_successes = 0;  // scripted grasps that hold
  std::map<std::string, int32_t> not_computed_reasons;
};

// fingers: the daemon's sensor names for finger A and B (its config's [[sensor]] names).
Result<ScoreReport> score_live_run(const std::string& truth_path,
                                   const std::string& predictions_path,
                                   const std::vector<std::string>& fingers);

std::string format_score(const ScoreReport& report);       // the table the demo prints
std::string format_score_json(const ScoreReport& report);  // one JSON object

}  // namespace tlvlink::score
