#include "quantize_flags.h"

#include <cstdio>

namespace tlvlink::cli {

void QuantizeDataFlags::add_to(CLI::App& app) {
  // Either --calib (repeatable: several sources) or --calib-images: a dataset's layout without
  // its index is an error in --calib, never a silent switch to its image files; --calib-images
  // says so explicitly.
  CLI::Option_group* source = app.add_option_group("calibration data");
  source
      ->add_option("--calib", calib,
                   "Calibration data: a Touch100k / Touch-and-Go / Feel dataset dir (or Feel "
                   ".h5), a folder of images (JPEG/PNG/PPM/PGM), or 'extreme' (the "
                   "simulator's extreme set). Repeatable (up to 8): each source gives an equal "
                   "share of --calib-count and --heldout-count, interleaved, e.g. the "
                   "encoder's training set and the grasp episodes the heads read")
      ->allow_extra_args(false);  // one path per --calib: the model positional stays apart
  source->add_option("--calib-images", calib_images,
                     "Calibrate on every image file under DIR (recursively), whatever its "
                     "layout; same as --calib DIR --calib-format images");
  source->require_option(1);
  app.add_option(
      "--problems", problems,
      "Write every load problem (file:line: kind: reason) to FILE; stderr shows the first 10");
  app.add_option("--calib-format", calib_format,
                 "auto, touch100k, tag, feel, feel-repacked, images or extreme")
      ->check(
          CLI::IsMember({"auto", "touch100k", "tag", "feel", "feel-repacked", "images", "extreme"}))
      ->capture_default_str();
  app.add_option("--calib-split", calib_split,
                 "Dataset split to draw frames from: all, train or test (recorded split of a "
                 "tlvlink-generated set, else the session/object hash tools/eval uses)")
      ->check(CLI::IsMember({"all", "train", "test"}))
      ->capture_default_str();
  app.add_option("--calib-count,-n", calib_count, "Calibration frames (seeded selection)")
      ->check(CLI::Range(int64_t{1}, quantize::kMaxCalibrationFrames))
      ->capture_default_str();
  app.add_option("--heldout-count", heldout_count,
                 "Held-out frames for the error report (never the calibration frames' sessions)")
      ->check(CLI::Range(int64_t{0}, quantize::kMaxCalibrationFrames))
      ->capture_default_str();
  app.add_option("--seed,-s", seed, "Seed of the frame selection")->capture_default_str();
  app.add_option("--ema-constant", averaging_constant,
                 "Weight of each new frame in the moving-average min/max (method ema)")
      ->check(CLI::Range(1e-6, 1.0))
      ->capture_default_str();
}

quantize::CalibDataOptions QuantizeDataFlags::options() const {
  quantize::CalibDataOptions o;
  o.paths = calib_images.empty() ? calib : std::vector<std::string>{calib_images};
  auto format = quantize::parse_calib_format(calib_format);  // validated by the flag's IsMember
  o.format = format.ok() ? *format : quantize::CalibFormat::kAuto;
  if (!calib_images.empty()) o.format = quantize::CalibFormat::kImages;
  o.split = calib_split == "train"  ? datasets::Split::kTrain
            : calib_split == "test" ? datasets::Split::kTest
                                    : datasets::Split::kAll;
  o.calib_count = calib_count;
  o.heldout_count = heldout_count;
  o.seed = seed;
  o.on_note = [](const std::string& note) {
    std::fprintf(stderr, "tlvlink quantize: %s\n", note.c_str());
  };
  return o;
}

}  // namespace tlvlink::cli
