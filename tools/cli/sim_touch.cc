// tlvlink sim touch100k|tag -o DIR: generated touch sessions in the Touch100k or Touch-and-Go
// format (tools/datasets/README.md).

#include <cstdio>
#include <string>

#include "common.h"
#include "sim_commands.h"
#include "tlvlink/io/format.h"
#include "tlvlink/sim/sets.h"

namespace tlvlink::cli {
namespace {

constexpr const char* kSensorInstancesHelp =
    "Simulated sensor instances to randomize over: each differs in LED gains (+-15 %), "
    "background non-uniformity, white balance and exposure; each session is recorded on one, "
    "drawn from (seed, session). 1 = one sensor for the whole set (a model trained on it does "
    "not transfer to another instance)";

struct TouchFlags {
  std::string format;  // "touch100k" or "tag"
  std::string output_dir;
  int sessions = 100;
  int frames_per_session = 10;
  uint64_t seed = 1;
  std::string sensor = "gelsight-mini";
  int vision_height = 240, vision_width = 320;
  bool markers = false;
  double markers_fraction = 0;
  int sensor_instances = 1;
  int jpeg_quality = 90;
  bool jpeg_full_chroma = false;
  double test_fraction = 0.2;
  bool no_sidecar = false;
  int threads = 1;
};

int run_touch(const TouchFlags& f) {
  const char* command = f.format == "tag" ? "sim tag" : "sim touch100k";
  sim::TouchSetJob job;
  job.generator.sessions = f.sessions;
  job.generator.frames_per_session = f.frames_per_session;
  job.generator.sensor = f.sensor;
  job.generator.vision_height = f.vision_height;
  job.generator.vision_width = f.vision_width;
  job.generator.markers = f.markers;
  job.generator.markers_fraction = f.markers_fraction;
  job.generator.seed = f.seed;
  job.generator.sensor_instances = f.sensor_instances;
  job.format =
      f.format == "tag" ? sim::TouchSetFormat::kTouchAndGo : sim::TouchSetFormat::kTouch100k;
  job.writer.jpeg_quality = f.jpeg_quality;
  job.writer.jpeg_full_chroma = f.jpeg_full_chroma;
  job.writer.test_fraction = f.test_fraction;
  job.writer.sidecar = !f.no_sidecar;
  job.dir = f.output_dir;
  job.threads = f.threads;
  job.progress_label = command;
  auto sum = sim::write_touch_set(job);
  if (!sum.ok()) return report_error(command, sum.error());
  std::printf("wrote %lld samples (%lld sessions: %lld train, %lld test; %lld files, %s) to %s\n",
              static_cast<long long>(sum->items), static_cast<long long>(sum->objects),
              static_cast<long long>(sum->objects - sum->test_objects),
              static_cast<long long>(sum->test_objects), static_cast<long long>(sum->files),
              tools::human_bytes(static_cast<size_t>(sum->bytes)).c_str(), f.output_dir.c_str());
  return kExitOk;
}

void add_touch_command(CLI::App& sim, int& exit_code, const char* name, const char* help) {
  auto f = std::make_shared<TouchFlags>();
  f->format = name;
  CLI::App* cmd = sim.add_subcommand(name, help);
  cmd->add_option("-o,--output", f->output_dir, "Output directory (created; must not hold a set)")
      ->required();
  cmd->add_option("--sessions", f->sessions, "Sessions (one object each)")
      ->check(CLI::Range(1, 10'000'000))
      ->capture_default_str();
  cmd->add_option("--frames-per-session", f->frames_per_session, "Frames (presses) per session")
      ->check(CLI::Range(1, 100'000))
      ->capture_default_str();
  cmd->add_option("-s,--seed", f->seed, "Seed; sample i depends only on (seed, i)")
      ->capture_default_str();
  cmd->add_option("--sensor", f->sensor,
                  "Sensor profile: gelsight-mini, digit, digit-640x480, gelsight-r1.5; or "
                  "several separated by commas (each session on one, drawn from (seed, "
                  "session): a mixed-profile set)")
      ->capture_default_str();
  cmd->add_option("--vision-height", f->vision_height, "Vision image height")
      ->check(CLI::Range(1, 8192))
      ->capture_default_str();
  cmd->add_option("--vision-width", f->vision_width, "Vision image width")
      ->check(CLI::Range(1, 8192))
      ->capture_default_str();
  cmd->add_flag("--markers", f->markers, "Render the marker grid");
  cmd->add_option("--markers-fraction", f->markers_fraction,
                  "Share of sessions whose gel has markers, drawn per session (gels come with "
                  "and without them); --markers = all")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--sensor-instances", f->sensor_instances, kSensorInstancesHelp)
      ->check(CLI::Range(1, sim::kMaxSensorInstances))
      ->capture_default_str();
  cmd->add_option("--jpeg-quality", f->jpeg_quality, "Quality of the stored JPEGs")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd->add_flag("--jpeg-full-chroma", f->jpeg_full_chroma, kJpegFullChromaHelp);
  cmd->add_option("--test-fraction", f->test_fraction,
                  "Share of sessions in the test split (train/test never share a session)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_flag("--no-sidecar", f->no_sidecar,
                "Do not write the tlvlink_sim_*.jsonl ground-truth sidecars");
  cmd->add_option("-t,--threads", f->threads,
                  "Generator threads (output is identical for any count)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->footer(kExitCodeFooter);
  cmd->callback([f, &exit_code] { exit_code = run_touch(*f); });
}

}  // namespace

void add_sim_touch_commands(CLI::App& sim, int& exit_code) {
  add_touch_command(sim, exit_code, "touch100k",
                    "Generate a Touch100k-format set: touch/, vision/, data_list.json (img, "
                    "sentence_desc, phrase_desc)");
  add_touch_command(sim, exit_code, "tag",
                    "Generate a Touch-and-Go-format set: session folders of gelsight_frame/ and "
                    "video_frame/ JPEGs, material / hard / rough label files split by session");
}

}  // namespace tlvlink::cli
