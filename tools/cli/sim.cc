// tlvlink sim: the GelSight simulator on the command line: datasets in the Touch100k,
// Touch-and-Go and Feel formats, single frames, the extreme set, dataset statistics.

#include <cstdio>
#include <memory>
#include <string>

#include "common.h"
#include "sim_commands.h"

namespace tlvlink::cli {

void add_sim_command(CLI::App& app, int& exit_code) {
  CLI::App* sim = app.add_subcommand(
      "sim",
      "GelSight simulator: generate Touch100k / Touch-and-Go / Feel datasets, render "
      "frames and the extreme set, print dataset statistics");
  auto stats_dir = std::make_shared<std::string>();
  CLI::Option* stats =
      sim->add_option("--stats", *stats_dir,
                      "Print the statistics of the Touch100k-format set in this directory "
                      "(same as `tlvlink sim stats DIR`)");
  // --top / --json go with --stats (the `sim stats` subcommand has its own).
  auto stats_top = std::make_shared<int>(20);
  auto stats_json = std::make_shared<bool>(false);
  sim->add_option("--top", *stats_top, "With --stats: how many of the most frequent phrases")
      ->check(CLI::Range(1, 100000))
      ->needs(stats);
  sim->add_flag("--json", *stats_json, "With --stats: print JSON")->needs(stats);
  sim->require_subcommand(0, 1);
  sim->footer(kExitCodeFooter);
  add_sim_touch_commands(*sim, exit_code);
  add_sim_feel_command(*sim, exit_code);
  add_sim_frame_command(*sim, exit_code);
  add_sim_extreme_command(*sim, exit_code);
#if defined(TLVLINK_HAVE_SIM_SCENARIO)
  add_sim_scenario_command(*sim, exit_code);
#endif
  add_sim_stats_command(*sim, exit_code);
  // --stats is a command of its own: combining it with a subcommand is a usage error.
  for (CLI::App* sub : sim->get_subcommands([](CLI::App*) { return true; })) sub->excludes(stats);
  sim->callback([sim, stats_dir, stats_top, stats_json, &exit_code] {
    if (!sim->get_subcommands().empty()) return;
    if (stats_dir->empty()) {
      std::fprintf(stderr, "%s", sim->help().c_str());
      std::fprintf(stderr, "tlvlink sim: give a subcommand or --stats DIR\n");
      exit_code = kExitUsage;
      return;
    }
    exit_code = run_sim_stats(*stats_dir, *stats_top, true, *stats_json);
  });
}

}  // namespace tlvlink::cli
