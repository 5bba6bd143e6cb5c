#pragma once
// The pieces of `tlvlink sim` (sim.cc registers them): dataset generation in the three formats,
// single frames, the extreme set, and Touch100k statistics. Private to tools/cli.

#include <CLI/CLI.hpp>

#include <string>

namespace tlvlink::cli {

void add_sim_touch_commands(CLI::App& sim, int& exit_code);  // touch100k, tag
void add_sim_feel_command(CLI::App& sim, int& exit_code);
void add_sim_frame_command(CLI::App& sim, int& exit_code);
void add_sim_extreme_command(CLI::App& sim, int& exit_code);
void add_sim_scenario_command(CLI::App& sim, int& exit_code);  // needs runtime/capture
void add_sim_stats_command(CLI::App& sim, int& exit_code);
// --jpeg-full-chroma's help, shared by the writers of touch frames.
inline constexpr const char* kJpegFullChromaHelp =
    "Store the touch frames' JPEGs 4:4:4 instead of 4:2:0: a GelSight shows fine surface "
    "normals in its colours, which 4:2:0 halves (with --jpeg-quality 100: within a few DN of "
    "the rendered frame)";
// `tlvlink sim stats DIR` and `tlvlink sim --stats DIR`.
int run_sim_stats(const std::string& dir, int top_n, bool check_files, bool json);

}  // namespace tlvlink::cli
