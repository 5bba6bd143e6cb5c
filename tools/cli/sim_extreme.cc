// tlvlink sim extreme -o DIR: renders the named extreme set (tlvlink/sim/extreme.h) to PPM
// files plus extreme.jsonl (name, what, frame size, pixel range, contact state), and checks
// that every invalid parameter set is rejected naming its field.

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>

#include "cli/common.h"
#include "cli/sim_commands.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/pnm.h"
#include "tlvlink/sim/extreme.h"

namespace tlvlink::cli {
namespace {

struct ExtremeFlags {
  std::string output_dir;
  uint64_t seed = 1;
  bool list = false;
};

nlohmann::ordered_json contact_json(const sim::ContactState& c) {
  return {{"in_contact", c.in_contact},
          {"force_n", c.force_n},
          {"press_mm", c.press_mm},
          {"kappa", c.kappa},
          {"contact_area_mm2", c.contact_area_mm2},
          {"slip_ratio", c.slip_ratio},
          {"gross_slip", c.gross_slip},
          {"markers_deviating", c.markers_deviating}};
}

int run_extreme(const ExtremeFlags& f) {
  const char* command = "sim extreme";
  if (f.list) {
    for (const sim::ExtremeCase& c : sim::extreme_cases())
      std::printf("%-28.*s %.*s\n", static_cast<int>(c.name.size()), c.name.data(),
                  static_cast<int>(c.what.size()), c.what.data());
    return kExitOk;
  }
  if (f.output_dir.empty())
    return report_error(command,
                        Error(ErrorCode::kInvalidArgument, "-o DIR is required (or --list)"));
  std::error_code ec;
  std::filesystem::create_directories(f.output_dir, ec);
  if (ec)
    return report_error(command, Error::make(ErrorCode::kIo, "cannot create directory '%s': %s",
                                             f.output_dir.c_str(), ec.message().c_str()));
  std::string lines;
  int rendered = 0;
  for (const sim::ExtremeCase& c : sim::extreme_cases()) {
    const std::string name(c.name);
    auto renderer = sim::Renderer::create(c.sensor, f.seed);
    if (!renderer.ok())
      return report_error(command, renderer.error().with_context("%s", name.c_str()));
    sim::Frame frame;
    if (Status s = (*renderer)->render(c.scene, c.options, f.seed, frame); !s.ok())
      return report_error(command, s.error().with_context("%s", name.c_str()));
    tools::Image image{frame.width, frame.height, 3, frame.rgb};
    const std::string path = (std::filesystem::path(f.output_dir) / (name + ".ppm")).string();
    if (Status s = tools::write_pnm(path, image); !s.ok()) return report_error(command, s.error());
    const auto [lo, hi] = std::minmax_element(frame.rgb.begin(), frame.rgb.end());
    nlohmann::ordered_json j = {{"name", name},
                                {"what", std::string(c.what)},
                                {"sensor", std::string(c.sensor.name)},
                                {"height", frame.height},
                                {"width", frame.width},
                                {"min", frame.rgb.empty() ? 0 : *lo},
                                {"max", frame.rgb.empty() ? 0 : *hi},
                                {"contact", contact_json(frame.state)}};
    lines += j.dump() + "\n";
    ++rendered;
  }
  const std::string index = (std::filesystem::path(f.output_dir) / "extreme.jsonl").string();
  if (Status s = tools::write_file(
          index, std::as_bytes(std::span<const char>(lines.data(), lines.size())));
      !s.ok())
    return report_error(command, s.error());
  int rejected = 0, total = 0;
  for (const sim::InvalidCase& c : sim::invalid_parameter_cases()) {
    ++total;
    const Status s = sim::validate_all(c.sensor, c.scene, c.options);
    if (!s.ok() && std::string(s.error().message()).find(std::string(c.field)) != std::string::npos)
      ++rejected;
    else
      std::fprintf(stderr, "tlvlink sim extreme: invalid case %s was not rejected naming '%.*s'\n",
                   c.name.c_str(), static_cast<int>(c.field.size()), c.field.data());
  }
  std::printf(
      "rendered %d extreme cases to %s (index extreme.jsonl); %d/%d invalid parameter "
      "sets rejected naming their field\n",
      rendered, f.output_dir.c_str(), rejected, total);
  return rejected == total ? kExitOk : kExitFailure;
}

}  // namespace

void add_sim_extreme_command(CLI::App& sim, int& exit_code) {
  auto f = std::make_shared<ExtremeFlags>();
  CLI::App* cmd = sim.add_subcommand(
      "extreme",
      "Render the extreme set (no contact, saturated LEDs, 1 kPa..1e12 Pa, mu = 0, "
      "JPEG q1, ...) to DIR/<name>.ppm + extreme.jsonl and check the invalid sets");
  cmd->add_option("-o,--output", f->output_dir, "Output directory (created)");
  cmd->add_option("-s,--seed", f->seed, "Sensor and noise seed")->capture_default_str();
  cmd->add_flag("--list", f->list, "Only list the case names");
  cmd->footer(kExitCodeFooter);
  cmd->callback([f, &exit_code] { exit_code = run_extreme(*f); });
}

}  // namespace tlvlink::cli
