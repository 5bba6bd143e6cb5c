// `tlvlink sim scenario`: two simulated fingers' camera streams + ground truth for live runs.
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "common.h"
#include "sim_commands.h"
#include "tlvlink/io/progress.h"
#include "tlvlink/sim/scenario.h"

namespace tlvlink::cli {
namespace {

struct ScenarioFlags {
  std::string output_dir;
  std::string sensor = "gelsight-mini";
  int32_t grasps = 6, presses = 4, jpeg_quality = 90;
  uint64_t seed = 1;
  bool markers = false, offline = false, overwrite = false;
};

int run_scenario(const ScenarioFlags& f) {
  sim::ScenarioOptions o;
  o.sensor = f.sensor;
  o.grasps = f.grasps;
  o.presses = f.presses;
  o.seed = f.seed;
  o.jpeg_quality = f.jpeg_quality;
  o.markers = f.markers;
  o.offline = f.offline;
  o.overwrite = f.overwrite;
  std::optional<tools::Progress> progress;
  auto r = sim::write_scenario(o, f.output_dir, [&](int64_t done, int64_t total) {
    if (!progress) progress.emplace("scenario frames", total);
    progress->set(done);
  });
  if (progress) progress->finish();
  if (!r.ok()) return report_error("sim scenario", r.error());
  std::printf(
      "scenario %s: %s, %d grasps (%d succeed) + %d presses, %.1f s = %lld frames per finger; "
      "%lld rendered, %.1f MB in A.tlvraw + B.tlvraw%s; truth.jsonl; written in %.1f s\n",
      f.output_dir.c_str(), f.sensor.c_str(), f.grasps, r->grasps_succeeding, f.presses, r->seconds,
      static_cast<long long>(r->frames), static_cast<long long>(r->rendered),
      static_cast<double>(r->file_bytes) / 1e6,
      f.offline ? " + A/B.offline.tlvraw + A/B.dataset.tlvraw" : "", r->render_seconds);
  return kExitOk;
}

}  // namespace

void add_sim_scenario_command(CLI::App& sim, int& exit_code) {
  auto f = std::make_shared<ScenarioFlags>();
  CLI::App* cmd = sim.add_subcommand(
      "scenario",
      "Record two simulated fingers streaming as their cameras do (Mini: MJPEG 3280x2464 at 25 "
      "fps; DIGIT: YUYV 320x240 at 60 fps) through scripted grasps and presses: DIR/A.tlvraw, "
      "DIR/B.tlvraw (replay them with tlvlinkd's replay source) and DIR/truth.jsonl (for "
      "`tlvlink score`)");
  cmd->add_option("-o,--output", f->output_dir, "Output directory (created)")->required();
  cmd->add_option("--sensor", f->sensor, "Sensor profile")->capture_default_str();
  cmd->add_option("--grasps", f->grasps, "Grasp + lift events (0..1000)")->capture_default_str();
  cmd->add_option("--presses", f->presses, "Single-finger presses (0..1000)")
      ->capture_default_str();
  cmd->add_option("-s,--seed", f->seed, "Objects, sensors and noise")->capture_default_str();
  cmd->add_option("--jpeg-quality", f->jpeg_quality, "MJPEG quality (1..100)")
      ->capture_default_str();
  cmd->add_flag("--markers", f->markers, "A gel with printed markers");
  cmd->add_flag("--offline", f->offline,
                "Also record the processed frames of the upright view twice: exactly (RGB24, "
                "bit for bit) into DIR/A.offline.tlvraw and B.offline.tlvraw, and as the "
                "datasets store them (JPEG q90, 4:2:0) into DIR/A.dataset.tlvraw and "
                "B.dataset.tlvraw; replayed by tlvlinkd (format rgb24 / mjpeg, the view's size, "
                "crop 0, jpeg_scale 1, orientation upright) they give the offline image path's "
                "predictions of the same frames, and of the datasets' copy of them");
  cmd->add_flag("--overwrite", f->overwrite,
                "Replace the files of an earlier scenario in the directory");
  cmd->footer(kExitCodeFooter);
  cmd->callback([f, &exit_code] { exit_code = run_scenario(*f); });
}

}  // namespace tlvlink::cli
