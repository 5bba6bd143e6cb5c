#pragma once
// Calibration and held-out frames for `tlvlink quantize` and `quantize-sweep`: from a Touch100k,
// Touch-and-Go or Feel dataset (tlvlink::datasets loaders), a folder of images (JPEG / PPM / PGM /
// PNG), or the simulator's extreme set. Every frame goes through image::preprocess with the
// model's InputSpec: the same code inference uses.
//
// Selection is seeded and disjoint by group: items are grouped (session for Touch100k / TAG,
// object for Feel, folder for images), groups are ranked by a hash of (group, seed), the first
// groups become the held-out pool until it holds enough items, the rest the calibration pool.
// Held-out frames therefore never share a session/object with calibration frames (unless the
// data has a single group, which the summary states). Within a pool, items are taken in order
// of a hash of (key, seed). The extreme set renders the named scenes with `seed` for
// calibration and with other seeds (other sensor instance and noise) for the held-out frames.
//
// Several sources (`--calib A --calib B`: e.g. the encoder's training set and the grasp episodes
// the heads read, so the ranges and the bias correction see every kind of frame the board will):
// each source gives an equal share of both counts (the first sources one more when they do not
// divide), selected within it as above, and the frames are interleaved source by source
// (A0 B0 A1 B1 ...) so that any prefix, such as bias correction's first N frames, draws on every
// source alike.
//
// Memory: the selected frames are kept preprocessed, (calib + heldout) x H x W x C floats
// (250 frames at 128x128x3: 49 MB); counts are capped at kMaxCalibrationFrames.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "tlvlink/datasets/detect.h"
#include "tlvlink/datasets/report.h"
#include "tlvlink/datasets/split.h"
#include "tlvlink/error.h"
#include "tlvlink/metadata.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/quantizer.h"

namespace tlvlink::quantize {

inline constexpr int64_t kMaxCalibrationFrames = 4096;
// Sources per run (`--calib` given this many times at most).
inline constexpr size_t kMaxCalibrationSources = 8;

enum class CalibFormat : uint8_t {
  kAuto = 0,
  kTouch100k,
  kTag,
  kFeel,
  kFeelRepacked,
  kImages,
  kExtreme
};
const char* calib_format_name(CalibFormat format);  // "auto", "touch100k", "tag", "feel", ...
Result<CalibFormat> parse_calib_format(const std::string& name);
CalibFormat calib_format_of(datasets::DatasetFormat format);
// "extreme" -> kExtreme; a dataset -> its format by the datasets' one rule
// (datasets::probe_dataset_format); otherwise a directory holding images (or folders) -> images.
// Errors: the path does not exist (kIo), ambiguous markers or nothing usable (kFormat, naming
// what was looked for).
Result<CalibFormat> detect_calib_format(const std::string& path);

struct CalibDataOptions {
  // Datasets or image dirs, or "extreme": 1..kMaxCalibrationSources sources.
  std::vector<std::string> paths;
  CalibFormat format = CalibFormat::kAuto;  // of every source (kAuto: each its own)
  int64_t calib_count = 200;                // over all sources
  int64_t heldout_count = 50;
  uint64_t seed = 1;
  // Which split of a dataset to draw from, by the datasets' rule (tlvlink/datasets/detect.h:
  // recorded for tlvlink-generated sets, else the session/object hash eval uses). kAll for
  // images / extreme.
  datasets::Split split = datasets::Split::kAll;
  bool progress = true;  // tools/io/progress.h on stderr
  // Called with "skipping <why>" for each unreadable image of an image folder (it is counted in
  // the summary either way).
  std::function<void(const std::string& note)> on_note;
  // Receives every load problem of the dataset loaders (the command shows and logs them);
  // borrowed for the call, may be null.
  datasets::ProblemEcho* problems = nullptr;
};

struct CalibData {
  std::vector<CalibFormat> formats;             // one per source, in `paths` order
  std::vector<std::vector<float>> calibration;  // preprocessed graph-input-0 frames
  std::vector<std::vector<float>> heldout;
  std::vector<std::string> calibration_keys, heldout_keys;
  std::string summary;  // one paragraph per source: items, groups, selection, load problems
};

// "touch100k", or "touch100k+feel-repacked" for several sources.
std::string calib_formats_name(const std::vector<CalibFormat>& formats);

// Errors: missing (kIo) or undetectable (kFormat) data, no usable frame (kFormat), a
// preprocessing failure (naming the item), counts outside [1, kMaxCalibrationFrames] (heldout
// may be 0; kInvalidArgument), no source, more than kMaxCalibrationSources or more sources than
// calibration frames (kInvalidArgument). Errors of a source name its path.
Result<CalibData> load_calib_data(const CalibDataOptions& options, const InputSpec& spec);

// quantize::calibrate over in-memory frames with a "quantize: calibrating" progress line (one
// summary line when `progress` is false).
Result<CalibrationStats> calibrate_frames(const Model& model,
                                          const std::vector<std::vector<float>>& frames,
                                          double averaging_constant, bool progress);

}  // namespace tlvlink::quantize
