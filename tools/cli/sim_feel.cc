// tlvlink sim feel -o DIR: generated grasp episodes in Feel's HDF5 files or, with --repacked,
// TLV-Link's jpg + info JSON-lines layout.

#include <algorithm>
#include <cstdio>
#include <string>

#include "common.h"
#include "sim_commands.h"
#include "tlvlink/io/format.h"
#include "tlvlink/sim/sets.h"

namespace tlvlink::cli {
namespace {

struct FeelFlags {
  std::string output_dir;
  int objects = 20;
  int grasps_per_object = 10;
  uint64_t seed = 1;
  std::string sensor = "gelsight-mini";
  int vision_height = 240, vision_width = 320;
  bool no_markers = false;
  double markers_fraction = -1;  // unset: every gel has markers unless --no-markers
  int sensor_instances = 1;
  bool repacked = false;
  int records_per_file = 100;
  int deflate_level = 1;
  int camera_jpeg_quality = 95;
  bool live_path = false;
  double live_path_fraction = 0;
  int jpeg_quality = 95;
  bool jpeg_full_chroma = false;
  int quarter_turns = 0;
  double test_fraction = 0.2;
  bool no_sidecar = false;
  int threads = 1;
  bool oracle = false;
};

int run_feel(const FeelFlags& f) {
  const char* command = "sim feel";
  sim::GraspSetJob job;
  sim::GraspSetOptions& gen = job.generator;
  gen.objects = f.objects;
  gen.grasps_per_object = f.grasps_per_object;
  gen.sensor = f.sensor;
  gen.vision_height = f.vision_height;
  gen.vision_width = f.vision_width;
  gen.markers = !f.no_markers && f.markers_fraction < 0;
  gen.markers_fraction = std::max(f.markers_fraction, 0.0);
  gen.seed = f.seed;
  gen.sensor_instances = f.sensor_instances;
  gen.live_path = f.live_path;
  gen.live_path_fraction = f.live_path_fraction;
  datasets::FeelWriterOptions& wo = job.writer;
  wo.jpeg_quality = f.jpeg_quality;
  wo.jpeg_full_chroma = f.jpeg_full_chroma;
  wo.test_fraction = f.test_fraction;
  wo.sidecar = !f.no_sidecar;
  wo.records_per_file = f.records_per_file;
  wo.deflate_level = f.deflate_level;
  wo.camera_jpeg_quality = f.camera_jpeg_quality;
  wo.gelsight_quarter_turns = f.quarter_turns;
  job.repacked = f.repacked;
  job.dir = f.output_dir;
  job.threads = f.threads;
  job.progress_label = command;
  auto result = sim::write_grasp_set(job);
  if (!result.ok()) return report_error(command, result.error());
  const datasets::WriteSummary& sum = result->written;
  std::printf(
      "wrote %lld grasps of %lld objects (%lld test objects), %.1f %% still held after "
      "the lift; %lld files, %s in %s\n",
      static_cast<long long>(sum.items), static_cast<long long>(sum.objects),
      static_cast<long long>(sum.test_objects),
      sum.items > 0 ? 100.0 * static_cast<double>(result->gripping) / static_cast<double>(sum.items)
                    : 0.0,
      static_cast<long long>(sum.files), tools::human_bytes(static_cast<size_t>(sum.bytes)).c_str(),
      f.output_dir.c_str());
  if (f.oracle) {
    constexpr int64_t kOracleSamples = 20000;
    std::printf("oracle accuracy from the visible variables (%lld fresh episodes): %.3f\n",
                static_cast<long long>(kOracleSamples),
                sim::grasp_oracle_accuracy(gen, kOracleSamples));
  }
  return kExitOk;
}

}  // namespace

void add_sim_feel_command(CLI::App& sim, int& exit_code) {
  auto f = std::make_shared<FeelFlags>();
  CLI::App* cmd = sim.add_subcommand(
      "feel",
      "Generate Feel-style grasp episodes (two fingers x before/during/after) as "
      "calandra_corl2017_NNN.h5 files, or TLV-Link's repacked layout with --repacked");
  cmd->add_option("-o,--output", f->output_dir, "Output directory (created; must not hold a set)")
      ->required();
  cmd->add_option("--objects", f->objects, "Objects (splits are by object)")
      ->check(CLI::Range(1, 1'000'000))
      ->capture_default_str();
  cmd->add_option("--grasps-per-object", f->grasps_per_object, "Grasps per object")
      ->check(CLI::Range(1, 100'000))
      ->capture_default_str();
  cmd->add_option("-s,--seed", f->seed, "Seed; episode i depends only on (seed, i)")
      ->capture_default_str();
  cmd->add_option("--sensor", f->sensor,
                  "Sensor profile, or several separated by commas (\"gelsight-mini,digit\"): "
                  "then each object's grasps are recorded on one, drawn per object")
      ->capture_default_str();
  cmd->add_option("--vision-height", f->vision_height, "kinectA_rgb height")
      ->check(CLI::Range(1, 8192))
      ->capture_default_str();
  cmd->add_option("--vision-width", f->vision_width, "kinectA_rgb width")
      ->check(CLI::Range(1, 8192))
      ->capture_default_str();
  CLI::Option* no_markers =
      cmd->add_flag("--no-markers", f->no_markers, "Render without the marker grid");
  cmd->add_option("--markers-fraction", f->markers_fraction,
                  "Share of objects whose grasps are recorded on gels with markers, drawn per "
                  "object (default: all of them)")
      ->check(CLI::Range(0.0, 1.0))
      ->excludes(no_markers);
  cmd->add_option("--sensor-instances", f->sensor_instances,
                  "Simulated sensor instances to randomize over: each differs in LED gains "
                  "(+-15 %), background non-uniformity, white balance and exposure; fingers A and "
                  "B are two sensors, each drawn per episode from (seed, episode, finger). 1 = "
                  "one sensor for both fingers and the whole set")
      ->check(CLI::Range(1, sim::kMaxSensorInstances))
      ->capture_default_str();
  CLI::Option* repacked =
      cmd->add_flag("--repacked", f->repacked,
                    "TLV-Link's layout: data/<touch_dir>/gelsight*.jpg + {train,test}_info.json");
  // An option of the other layout would be silently ignored: refuse it, naming the layout.
  cmd->add_option("--records-per-file", f->records_per_file, "HDF5: grasps per file")
      ->check(CLI::Range(1, 10000))
      ->excludes(repacked)
      ->capture_default_str();
  cmd->add_option("--deflate", f->deflate_level, "HDF5: deflate level (0 = none)")
      ->check(CLI::Range(0, 9))
      ->excludes(repacked)
      ->capture_default_str();
  cmd->add_option("--camera-jpeg-quality", f->camera_jpeg_quality,
                  "JPEG round trip of every frame before storing, like the rig's MJPEG camera "
                  "(0 = none)")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  CLI::Option* live_path = cmd->add_flag(
      "--live-path", f->live_path,
      "Every GelSight frame through its sensor's raw camera output and the board's "
      "decoder, as tlvlinkd sees it (the Mini's MJPEG 3280x2464 decoded at 1/8, DIGIT's "
      "YUYV) instead of --camera-jpeg-quality's round trip, which then applies to the "
      "vision frames only. Slower (~30 ms per Mini frame); the HDF5 layout stores the "
      "frames losslessly, --repacked compresses them again at --jpeg-quality");
  cmd->add_option("--live-path-fraction", f->live_path_fraction,
                  "Share of objects whose GelSight frames take --live-path's route, drawn per "
                  "object (independently of --markers-fraction); the others take "
                  "--camera-jpeg-quality's round trip. A grasp head fitted on both reads the "
                  "board's frames and the dataset's alike (0 = none)")
      ->check(CLI::Range(0.0, 1.0))
      ->excludes(live_path)
      ->capture_default_str();
  cmd->add_option("--jpeg-quality", f->jpeg_quality, "--repacked: quality of the stored JPEGs")
      ->check(CLI::Range(1, 100))
      ->needs(repacked)
      ->capture_default_str();
  cmd->add_flag("--jpeg-full-chroma", f->jpeg_full_chroma,
                std::string("--repacked: ") + kJpegFullChromaHelp)
      ->needs(repacked);  // the HDF5 files store no JPEGs of their own
  cmd->add_option("--quarter-turns", f->quarter_turns,
                  "HDF5: store GelSight frames rotated by this many quarter turns "
                  "counterclockwise (the published files are stored rotated)")
      ->check(CLI::Range(0, 3))
      ->excludes(repacked)
      ->capture_default_str();
  cmd->add_option("--test-fraction", f->test_fraction, "Share of objects in the test split")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_flag("--no-sidecar", f->no_sidecar,
                "Do not write the simulator metadata (HDF5 attribute / sidecar JSON-lines)");
  cmd->add_option("-t,--threads", f->threads,
                  "Generator threads (output is identical for any count)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_flag("--oracle", f->oracle,
                "Also print the accuracy an oracle reaches from the visible variables");
  cmd->footer(kExitCodeFooter);
  cmd->callback([f, &exit_code] { exit_code = run_feel(*f); });
}

}  // namespace tlvlink::cli
