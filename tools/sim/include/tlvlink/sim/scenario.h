#pragma once
// A live scenario: two simulated fingers recorded as the cameras stream them (the sensor's raw
// format, size and frame rate), performing scripted scenes whose ground truth is written beside
// them, so a live run of tlvlinkd can be scored.
//
// Scenes, per event, on both fingers' own sensors (two physical sensor instances):
//   idle          the open gel (the contact gate's reference frames come from the lead-in)
//   grasp + lift  a simulated Feel episode animated: fingers close on the object (force ramp),
//                 hold it resting, lift (the episode's lift load: stick, partial or gross slip,
//                 or the object is gone), release. Label: the episode's is_gripping.
//   press         finger A alone presses an object (force ramp up and down), B stays open:
//                 light loads at the ramps' ends are where a contact gate can miss a touch.
// Static stretches reuse a few rendered frames (repeat records: the bytes are stored once), so a
// minute of two 8 MP MJPEG streams costs a few hundred renders and ~100 MB of disk.
//
// Output directory: A.tlvraw, B.tlvraw (capture/recording.h; B's frames 7 ms after A's, as two
// unsynchronised cameras are), optionally A/B.offline.tlvraw and A/B.dataset.tlvraw (below),
// commands.txt (the controller's closed / lifting marks of every grasp, tlvlinkd's
// command_script) and truth.jsonl (one "scenario" line, one "event" line per event,
// one "frame" line per frame and finger: contact, force, event). Written under temporary names
// and renamed at the end: an interrupted run leaves no partial scenario.

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "tlvlink/error.h"

namespace tlvlink::sim {

struct ScenarioOptions {
  std::string_view sensor = "gelsight-mini";  // a profile with a raw camera format and a
                                              // capture::SensorModel (its frame rate)
  int32_t grasps = 6;
  int32_t presses = 4;
  uint64_t seed = 1;
  int32_t jpeg_quality = 90;    // MJPEG sensors
  bool markers = false;         // a gel with printed markers (the grasp sets have them)
  int32_t static_variants = 3;  // distinct noise frames cycled through a static stretch
  int64_t finger_b_phase_ns = 7'000'000;
  // Also record each finger's processed frames (the renderer's frame of the view, upright):
  //   A/B.offline.tlvraw  the frames exactly, bit for bit (an RGB24 camera of the view's size):
  //                       the offline image path's predictions of the very same frames
  //   A/B.dataset.tlvraw  the frames as the datasets store them (JPEG q90, 4:2:0, of
  //                       image::encode_jpeg: a Touch100k or Feel set's bytes), an MJPEG camera
  // tlvlinkd replays them with format "rgb24" / "mjpeg", the view's width and height, crop 0,
  // jpeg_scale 1, orientation "upright". The two differ by the datasets' codec alone.
  bool offline = false;
  int32_t dataset_jpeg_quality = 90;  // A/B.dataset.tlvraw; the dataset writers' default
  // Replace the files of an earlier scenario in the directory; else one that exists (A.tlvraw,
  // B.tlvraw, truth.jsonl, commands.txt, the offline recordings) is an error naming it.
  bool overwrite = false;
};

struct ScenarioReport {
  int64_t frames = 0;      // per finger
  int64_t rendered = 0;    // both fingers: frames rendered (the rest are repeats)
  int64_t file_bytes = 0;  // both recordings
  double seconds = 0;      // the scenario's length
  int32_t grasps_succeeding = 0;
  double render_seconds = 0;  // wall time spent writing it
};

// Writes the scenario into `dir` (created if missing; existing scenario files are replaced
// only when the whole new one is written). progress(done, total) after every frame pair.
Result<ScenarioReport> write_scenario(const ScenarioOptions& options, const std::string& dir,
                                      const std::function<void(int64_t, int64_t)>& progress = {});

}  // namespace tlvlink::sim
