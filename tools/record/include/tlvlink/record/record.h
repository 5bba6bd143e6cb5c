#pragma once
// Recorded raw streams (runtime/capture/recording.h) made from files, so tlvlinkd's replay source
// can play image folders and the datasets (Touch100k, Touch-and-Go, Feel) as a camera would:
// one size and format for the whole stream, frames at a fixed rate, each image held for `hold`
// frames. JPEG files in an image folder are stored as they are (MJPEG, the camera's own bytes);
// every other frame is encoded as MJPEG at jpeg_quality. A frame of another size than the first is
// an error naming the file (a camera streams one size; nothing is resized silently). Written under
// a temporary name and renamed when complete.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::record {

enum class RecordSource : uint8_t {
  kImages,      // a folder of .jpg/.jpeg/.png/.ppm/.pnm files, in name order
  kTouch100k,   // a Touch100k-format set: its touch frames
  kTouchAndGo,  // a Touch-and-Go-format set: its touch frames
  kFeel,        // Feel episodes (HDF5 files or the repacked layout): one finger's before, during,
                // after frames per episode
};

struct RecordOptions {
  RecordSource source = RecordSource::kImages;
  std::string input;
  double fps = 25.0;          // (0, 1000]
  int32_t hold = 1;           // frames each image stays in view, 1..10000
  int64_t limit = 0;          // images taken at most; 0: all
  int32_t finger = 0;         // Feel: 0 = gelsightA, 1 = gelsightB
  int32_t jpeg_quality = 90;  // [1, 100]
  bool overwrite = false;
};

struct RecordReport {
  int64_t images = 0, frames = 0;
  int32_t width = 0, height = 0;
  int64_t file_bytes = 0;
  bool stored_as_is = false;  // JPEG files kept byte for byte
  // What was left out, one line each ("PATH: not a regular file (FIFO)", a dataset's
  // "path:line: kind: reason"): a folder member that is not a regular file, a dataset item that
  // did not load. The CLI prints them; none is skipped silently.
  std::vector<std::string> skipped;
};

Result<RecordReport> record_frames(const RecordOptions& options, const std::string& out_path);

// JPEG frames from elsewhere, one per call (false at the end); `name` names the frame in errors.
using JpegFrameSource = std::function<Result<bool>(std::vector<uint8_t>& jpeg, std::string& name)>;
// The same recording from a source of JPEG frames, kept byte for byte (options.source and
// options.input are not used; input names the source in errors): e.g. a stream recording's frame
// images (tools/foxglove frame_images.h, `tlvlink record --stream`).
Result<RecordReport> record_jpeg_frames(JpegFrameSource frames, const RecordOptions& options,
                                        const std::string& out_path);

}  // namespace tlvlink::record
