// tlvlink sim extreme -o DIR: renders the named extreme set (tlvlink/sim/extreme.h) to PPM
// files plus extreme.jsonl (name, what, frame size, pixel range, contact state), and checks
// that every invalid parameter set is rejected naming its field.

#include <cstdio>
#include <string>

#include "common.h"
#include "sim_commands.h"
#include "tlvlink/sim/extreme.h"
#include "tlvlink/sim/sets.h"

namespace tlvlink::cli {
namespace {

struct ExtremeFlags {
  std::string output_dir;
  uint64_t seed = 1;
  bool list = false;
};

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
  auto r = sim::write_extreme_set(f.output_dir, f.seed);
  if (!r.ok()) return report_error(command, r.error());
  for (const std::string& problem : r->unrejected)
    std::fprintf(stderr, "tlvlink sim extreme: invalid case %s\n", problem.c_str());
  std::printf(
      "rendered %d extreme cases to %s (index extreme.jsonl); %d/%d invalid parameter "
      "sets rejected naming their field\n",
      r->rendered, f.output_dir.c_str(), r->invalid_total - static_cast<int>(r->unrejected.size()),
      r->invalid_total);
  return r->all_rejected() ? kExitOk : kExitFailure;
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
