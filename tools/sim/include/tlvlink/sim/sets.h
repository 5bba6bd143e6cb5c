#pragma once
// Simulated sets written to disk in one call. Datasets (`tlvlink sim touch100k|tag|feel`): one
// generator per thread, the threaded batch generator (batch.h) feeding a tools/datasets writer in
// index order (the output is identical for any thread count), a progress line on stderr. The
// extreme set (`tlvlink sim extreme`): every named case as a PPM plus an index, and the check
// that every invalid parameter set is rejected naming its field.
//
//   TouchSetJob job;
//   job.generator.sessions = 100;  job.dir = "/tmp/t100k";  job.threads = 2;
//   auto written = write_touch_set(job);   // Result<datasets::WriteSummary>

#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/datasets/feel.h"
#include "tlvlink/datasets/writer.h"
#include "tlvlink/error.h"
#include "tlvlink/sim/generate.h"

namespace tlvlink::sim {

// The generators' options as JSON objects for datasets::WriterOptions::generator_json.
std::string touch_set_options_json(const TouchSetOptions& options);
std::string grasp_set_options_json(const GraspSetOptions& options);

enum class TouchSetFormat : uint8_t { kTouch100k, kTouchAndGo };

struct TouchSetJob {
  TouchSetOptions generator;
  TouchSetFormat format = TouchSetFormat::kTouch100k;
  datasets::WriterOptions writer;  // generator_json is filled from `generator`
  std::string dir;                 // created; must not hold a set
  int threads = 1;                 // generator threads
  std::string progress_label;      // the progress line's label
};
// Errors: bad generator options, the writer's (an existing set, I/O), a generator failure. The
// progress line is finished (with the bytes written) before an error is returned.
Result<datasets::WriteSummary> write_touch_set(const TouchSetJob& job);

struct GraspSetJob {
  GraspSetOptions generator;
  bool repacked = false;  // TLV-Link's jpg + info JSON-lines layout instead of Feel's HDF5
  datasets::FeelWriterOptions writer;  // generator_json is filled from `generator`
  std::string dir;
  int threads = 1;
  std::string progress_label;
};
struct GraspSetSummary {
  datasets::WriteSummary written;
  int64_t gripping = 0;  // episodes still held after the lift
};
Result<GraspSetSummary> write_grasp_set(const GraspSetJob& job);

struct ExtremeSetSummary {
  int rendered = 0;                     // DIR/<name>.ppm written, one line each in extreme.jsonl
  int invalid_total = 0;                // invalid parameter sets checked
  std::vector<std::string> unrejected;  // "<case> was not rejected naming '<field>'"
  bool all_rejected() const { return unrejected.empty(); }
};
// Renders extreme_cases() with `seed` into `dir` (created): <name>.ppm and extreme.jsonl (name,
// what, sensor, frame size, pixel range, contact state), then validates every
// invalid_parameter_cases() entry. Errors: I/O, a case that fails to render (naming it).
Result<ExtremeSetSummary> write_extreme_set(const std::string& dir, uint64_t seed);

}  // namespace tlvlink::sim
