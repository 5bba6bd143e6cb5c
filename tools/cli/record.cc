// `tlvlink record`: image folders and datasets as a camera's recorded stream (tlvlinkd replays it).
#include <cstdio>
#include <memory>
#include <string>

#include "common.h"
#include "record_stream.h"
#include "tlvlink/record/record.h"

namespace tlvlink::cli {
namespace {

struct RecordFlags {
  std::string images, touch100k, tag, feel, stream, output;
  int32_t sensor = 0;
  std::string finger = "A";
  record::RecordOptions options;
};

int run_record(RecordFlags f) {
  int given = 0;
  for (const auto& [path, source] : {std::pair{&f.images, record::RecordSource::kImages},
                                     {&f.touch100k, record::RecordSource::kTouch100k},
                                     {&f.tag, record::RecordSource::kTouchAndGo},
                                     {&f.feel, record::RecordSource::kFeel}}) {
    if (path->empty()) continue;
    ++given;
    f.options.source = source;
    f.options.input = *path;
  }
  if (!f.stream.empty()) {
    ++given;
    f.options.input = f.stream;
  }
  if (given != 1) {
    std::fprintf(
        stderr,
        "tlvlink record: give exactly one of --images, --touch100k, --tag, --feel, --stream\n");
    return kExitUsage;
  }
  f.options.finger = f.finger == "B" ? 1 : 0;
  auto r = f.stream.empty() ? record::record_frames(f.options, f.output)
                            : record_stream_images(f.stream, f.sensor, f.options, f.output);
  if (!r.ok()) return report_error("record", r.error());
  for (const std::string& s : r->skipped)
    std::fprintf(stderr, "tlvlink record: skipped %s\n", s.c_str());
  std::printf("recorded %s: %lld images as %lld frames (MJPEG %dx%d at %g fps%s), %.1f MB\n",
              f.output.c_str(), static_cast<long long>(r->images),
              static_cast<long long>(r->frames), r->width, r->height, f.options.fps,
              r->stored_as_is ? ", JPEG files kept as they are" : "",
              static_cast<double>(r->file_bytes) / 1e6);
  return kExitOk;
}

}  // namespace

void add_record_command(CLI::App& app, int& exit_code) {
  auto f = std::make_shared<RecordFlags>();
  CLI::App* cmd = app.add_subcommand(
      "record",
      "Make a camera recording (MJPEG, fixed frame rate) from an image folder or a dataset's touch "
      "frames, for tlvlinkd's replay source (source = \"replay\")");
  cmd->add_option("--images", f->images, "A folder of .jpg/.png/.ppm frames (name order)");
  cmd->add_option("--touch100k", f->touch100k, "A Touch100k-format set");
  cmd->add_option("--tag", f->tag, "A Touch-and-Go-format set");
  cmd->add_option("--feel", f->feel, "Feel episodes (HDF5 files or the repacked layout)");
  cmd->add_option(
      "--stream", f->stream,
      "A stream recording (.tlvrec or .mcap of `tlvlink listen --record`): the frame images the "
      "board sent (tlvlinkd frame_images), JPEGs kept as they are");
  cmd->add_option("--sensor", f->sensor, "--stream: the sensor whose images are taken (its index)")
      ->capture_default_str();
  cmd->add_option("--finger", f->finger, "Feel: gelsight A or B")
      ->check(CLI::IsMember({"A", "B"}))
      ->capture_default_str();
  cmd->add_option("-o,--output", f->output, "The recording to write")->required();
  cmd->add_option("--fps", f->options.fps, "Frame rate")->capture_default_str();
  cmd->add_option("--hold", f->options.hold, "Frames each image stays in view")
      ->capture_default_str();
  cmd->add_option("--limit", f->options.limit, "Images taken at most (0: all)")
      ->capture_default_str();
  cmd->add_option("--jpeg-quality", f->options.jpeg_quality, "For frames that are not JPEG files")
      ->capture_default_str();
  cmd->add_flag("--overwrite", f->options.overwrite, "Replace an existing recording");
  cmd->footer(kExitCodeFooter);
  cmd->callback([f, &exit_code] { exit_code = run_record(*f); });
}

}  // namespace tlvlink::cli
