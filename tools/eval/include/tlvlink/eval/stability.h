#pragma once
// Embedding stability: the same touch through every image path a user's frames can take, and
// how far the model's embedding and its heads' answers move (issue 29's stability suite).
//
// Simulated scenes (touch presses of unseen sensor instances, GelSight Mini and DIGIT) start
// from the renderer's processed frame, lossless; each path is compared with it:
//   jpeg-q95 / jpeg-q90 / jpeg-q75   the frame saved as a JPEG (4:2:0), as datasets and tools do
//   live                             the sensor's raw camera output through the board's decoder
//                                    (sim::LivePath: the Mini's MJPEG 3280x2464 q90 decoded at
//                                    1/8 and cropped, DIGIT's YUYV), what tlvlinkd sees
// Real frames (a folder of PNG/JPEG files, e.g. the developers' share of public GelSight
// frames) start from the file as stored: jpeg-q95/q90/q75 re-encodings, +3 DN and -3 DN.
//
//   auto report = eval::measure_stability(model, eval::StabilityOptions{});
//   std::puts(eval::format_stability(*report).c_str());

#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/eval/embeddings.h"
#include "tlvlink/model.h"

namespace tlvlink::eval {

// Targets of issue 29: the minimum cosine over every scene of a path, and the share of frames
// on which a trusted head gives the same answer as on the reference.
inline constexpr double kStabilityMinCosine = 0.97;
inline constexpr double kStabilityMinAgreement = 0.95;

struct StabilityOptions {
  int32_t scenes = 200;  // simulated scenes (one press each)
  uint64_t seed = 29;    // not a training or heads seed (1, 3, 2027)
  std::string sensors = "gelsight-mini,digit";
  int32_t sensor_instances = 16;  // drawn from this seed's instances: unseen ones
  double markers_fraction = 0.5;
  std::string real_frames_dir;  // empty: no real frames
  EmbedderOptions embedder;
};

struct HeadAgreement {
  std::string head;
  bool trusted = false;  // reported by default (heads::reported_by_default)
  int64_t same = 0, n = 0;
  double rate() const { return n > 0 ? static_cast<double>(same) / static_cast<double>(n) : 0; }
};

struct PathStability {
  std::string source;  // "simulated" or "real"
  std::string path;    // "jpeg-q90", "live gelsight-mini", "+3 DN", ...
  int64_t n = 0;
  double cos_min = 1, cos_p05 = 1, cos_median = 1;
  std::string worst;  // the item of cos_min ("scene 17 (digit, instance 3)", a file name)
  std::vector<HeadAgreement> heads;
  // cos_min >= kStabilityMinCosine and every trusted head agrees on >= kStabilityMinAgreement.
  bool meets_target() const;
};

struct StabilityReport {
  std::string model;
  int32_t scenes = 0;
  int64_t real_frames = 0;
  std::string real_note;  // why no real frames were measured, when none were
  std::vector<PathStability> paths;
  bool meets_target() const;
};

// Errors: the model (no embedding output), the simulator, an unreadable real-frames folder
// (a missing one is not an error: real_note says so).
Result<StabilityReport> measure_stability(const Model& model, const StabilityOptions& options);

// A table: one row per path, cosine min / p5 / median, each trusted head's agreement, and
// whether the row meets the targets.
std::string format_stability(const StabilityReport& report);
std::string stability_json(const StabilityReport& report);

}  // namespace tlvlink::eval
