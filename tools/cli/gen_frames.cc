// tlvlink gen-frames -o DIR: writes seeded synthetic tactile frames as binary PPM, so the
// runtime, `infer` and the demo have inputs before the simulator and real datasets exist.

#include <cinttypes>
#include <cstdio>
#include <filesystem>

#include "common.h"
#include "tlvlink/io/pnm.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink::cli {
namespace {

// A generated frame larger than this is a usage error (the PPM reader's limit is 16384 a side;
// these frames are for testing, a GelSight Mini's raw sensor is 3280x2464).
constexpr int kMaxFrameSide = 4096;

struct FramesOptions {
  std::string output_dir;
  int count = 8;
  int height = 240;  // GelSight Mini processed frame (240x320)
  int width = 320;
  uint64_t seed = 1;
};

int run_gen_frames(const FramesOptions& o) {
  std::error_code ec;
  std::filesystem::create_directories(o.output_dir, ec);
  if (ec) {
    return report_error("gen-frames",
                        Error::make(ErrorCode::kIo, "cannot create directory '%s': %s",
                                    o.output_dir.c_str(), ec.message().c_str()));
  }
  for (int i = 0; i < o.count; ++i) {
    tools::Image image;
    image.width = o.width;
    image.height = o.height;
    image.channels = 3;
    image.pixels =
        quantize::synthetic_touch_frame(o.height, o.width, o.seed + static_cast<uint64_t>(i));
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.ppm", i);
    const std::string path = (std::filesystem::path(o.output_dir) / name).string();
    if (Status s = tools::write_pnm(path, image); !s.ok())
      return report_error("gen-frames", s.error());
  }
  std::printf("wrote %d synthetic frames %dx%d (seeds %" PRIu64 "..%" PRIu64 ") to %s\n", o.count,
              o.width, o.height, o.seed, o.seed + static_cast<uint64_t>(o.count) - 1,
              o.output_dir.c_str());
  return kExitOk;
}

}  // namespace

void add_gen_frames_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<FramesOptions>();
  CLI::App* cmd = app.add_subcommand(
      "gen-frames",
      "Write seeded synthetic tactile frames (smooth LED illumination, contact blobs, sensor "
      "noise) as binary PPM files frame_0000.ppm, ...");
  cmd->add_option("-o,--output", o->output_dir, "Output directory (created if missing)")
      ->required();
  cmd->add_option("-n,--count", o->count, "Number of frames")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_option("--height", o->height, "Frame height in pixels")
      ->check(CLI::Range(1, kMaxFrameSide))
      ->capture_default_str();
  cmd->add_option("--width", o->width, "Frame width in pixels")
      ->check(CLI::Range(1, kMaxFrameSide))
      ->capture_default_str();
  cmd->add_option("-s,--seed", o->seed, "Seed of the first frame (frame i uses seed + i)")
      ->capture_default_str();
  cmd->footer(kExitCodeFooter);
  cmd->callback([o, &exit_code] { exit_code = run_gen_frames(*o); });
}

}  // namespace tlvlink::cli
