// `tlvlink contact --reference REF FRAME...`: the board's contact gate on your own frames,
// calibrated on your no-contact reference(s); prints each frame's score, the threshold and the
// decision (exit 0), so a user sees what the daemon's gate will say on their sensor.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "common.h"
#include "tlvlink/eval/contact_check.h"
#include "tlvlink/io/sensor_frame.h"

namespace tlvlink::cli {
namespace {

struct ContactFlags {
  std::vector<std::string> references, frames;
  eval::ContactCheckOptions o;
};

int run_contact(const ContactFlags& f) {
  auto check = eval::check_contact(f.references, f.frames, f.o);
  if (!check.ok()) return report_error("contact", check.error());
  std::printf(
      "reference: %zu frame(s), block noise %.2f DN; contact above %.2f DN (max of %.1f DN "
      "and %.0f x noise)\n",
      f.references.size(), static_cast<double>(check->noise_sigma_dn),
      static_cast<double>(check->threshold_dn), static_cast<double>(f.o.gate.min_threshold_dn),
      static_cast<double>(f.o.gate.noise_multiple));
  int contacts = 0;
  for (const eval::ContactCheckFrame& c : check->frames) {
    std::printf("%-8s score %7.2f DN  %s\n", c.contact ? "contact" : "none",
                static_cast<double>(c.score_dn), c.path.c_str());
    contacts += c.contact ? 1 : 0;
  }
  std::printf("%d of %zu frames in contact\n", contacts, check->frames.size());
  return kExitOk;
}

}  // namespace

void add_contact_command(CLI::App& app, int& exit_code) {
  auto f = std::make_shared<ContactFlags>();
  CLI::App* cmd = app.add_subcommand(
      "contact",
      "The board's contact gate on your frames: calibrated on no-contact reference frame(s) of "
      "your sensor (its colour cast, dust, markers and vignetting are subtracted), then each "
      "frame's score and decision");
  cmd->add_option("--reference,-r", f->references,
                  "A frame of the gel with nothing touching it (repeat for several: their spread "
                  "sets the noise)")
      ->required()
      ->allow_extra_args(false);  // -r A -r B: one frame per -r, the rest are the frames
  cmd->add_option("frames", f->frames, "Frames to classify (PNG, JPEG, PPM)")->required();
  cmd->add_option("--sensor", f->o.sensor,
                  "The sensor the frames come from (" + tools::known_sensor_names() +
                      "); default: detected from each frame's size");
  cmd->add_option("--min-threshold", f->o.gate.min_threshold_dn,
                  "Contact needs at least this block difference in DN (the daemon's "
                  "min_threshold_dn)")
      ->check(CLI::Range(0.5, 255.0));
  cmd->add_option("--noise-multiple", f->o.gate.noise_multiple,
                  "...and this many block-noise sigmas (the daemon's noise_multiple)")
      ->check(CLI::Range(1.0, 100.0));
  cmd->footer(kExitCodeFooter);
  cmd->callback([f, &exit_code] { exit_code = run_contact(*f); });
}

}  // namespace tlvlink::cli
