// `tlvlink`: inspect, run, verify and benchmark .tlvm models; generate the reference encoder.

#include <CLI/CLI.hpp>

#include <csignal>

#include "common.h"

int main(int argc, char** argv) {
  using namespace tlvlink::cli;
  // A file-size limit (ulimit -f) then fails the write with EFBIG, which AtomicFile reports
  // ("file size limit reached") after removing its temporary, instead of killing the process.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"tlvlink: inspect, run, verify and benchmark tlvlink (.tlvm) models"};
  app.footer(kExitCodeFooter);
  app.require_subcommand(1);
  int exit_code = kExitOk;
  add_inspect_command(app, exit_code);
  add_infer_command(app, exit_code);
  add_verify_command(app, exit_code);
  add_sign_commands(app, exit_code);
  add_bench_command(app, exit_code);
  add_gen_reference_command(app, exit_code);
  add_gen_frames_command(app, exit_code);
  add_sim_command(app, exit_code);
  add_convert_command(app, exit_code);
  add_quantize_command(app, exit_code);
  add_quantize_sweep_command(app, exit_code);
  add_train_command(app, exit_code);
  add_export_command(app, exit_code);
  add_adapt_command(app, exit_code);
  add_eval_command(app, exit_code);
  add_heads_command(app, exit_code);
  add_listen_command(app, exit_code);
  add_replay_command(app, exit_code);
  add_score_command(app, exit_code);
  add_stability_command(app, exit_code);
  add_contact_command(app, exit_code);
#if defined(TLVLINK_HAVE_BOARDS)
  add_strip_command(app, exit_code);
  add_flash_command(app, exit_code);
#endif
#if defined(TLVLINK_HAVE_SIM_SCENARIO)
  add_record_command(app, exit_code);
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the message and usage hint
    return kExitUsage;
  }
  return exit_code;
}
