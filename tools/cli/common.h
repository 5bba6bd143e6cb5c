#pragma once
// Shared pieces of the `tlvlink` subcommands: exit codes, error reporting, model loading and
// the --executor / --threads flags. Private to tools/cli.

#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "tlvlink/executor.h"
#include "tlvlink/model.h"

namespace tlvlink::cli {

// Exit codes of every subcommand (documented in the --help footer). Errors map to them by kind
// (report_error): a usage error (ErrorCode::kInvalidArgument) is 2, every other error (runtime,
// model, data) is 1.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  // runtime, model or data-file error; golden mismatch
inline constexpr int kExitUsage = 2;    // bad command-line arguments

inline constexpr const char* kExitCodeFooter =
    "Exit codes: 0 success; 1 runtime, model or data error (including a failed verify); "
    "2 usage error (bad arguments).";

// The exit code of an error: kExitUsage for ErrorCode::kInvalidArgument, else kExitFailure.
int exit_code_of(const Error& error);
// Prints "tlvlink <command>: error [code]: message" to stderr; returns exit_code_of(error).
int report_error(const char* command, const Error& error);

// tools::load_model (the path in every error).
Result<std::unique_ptr<Model>> load_model(const std::string& path);

// --executor and --threads, shared by infer / verify / bench / eval / heads fit.
struct ExecutorFlags {
  std::string executor = "xnnpack";
  int threads = 1;
  // threads_help: what --threads means for the command (default: XNNPACK's pool).
  void add_to(CLI::App& app, const char* threads_help = nullptr);
  ExecutorKind kind() const;  // validated by the flag's check
  ExecutorOptions options() const;
};
Result<std::unique_ptr<Executor>> create_executor(const Model& model, const ExecutorFlags& flags);

// Registration of each subcommand on the root app; `exit_code` receives the command's result.
void add_inspect_command(CLI::App& app, int& exit_code);
void add_infer_command(CLI::App& app, int& exit_code);
void add_verify_command(CLI::App& app, int& exit_code);
void add_sign_commands(CLI::App& app, int& exit_code);  // sign.cc: keygen, sign, upgrade
void add_bench_command(CLI::App& app, int& exit_code);
void add_gen_reference_command(CLI::App& app, int& exit_code);
void add_gen_frames_command(CLI::App& app, int& exit_code);
void add_sim_command(CLI::App& app, int& exit_code);
void add_convert_command(CLI::App& app, int& exit_code);   // convert.cc or convert_unavailable.cc
void add_quantize_command(CLI::App& app, int& exit_code);  // quantize.cc
void add_quantize_sweep_command(CLI::App& app, int& exit_code);  // quantize_sweep.cc
void add_train_command(CLI::App& app, int& exit_code);           // train.cc or train_unavailable.cc
void add_export_command(CLI::App& app, int& exit_code);     // export.cc or train_unavailable.cc
void add_adapt_command(CLI::App& app, int& exit_code);      // adapt.cc or train_unavailable.cc
void add_eval_command(CLI::App& app, int& exit_code);       // eval.cc
void add_heads_command(CLI::App& app, int& exit_code);      // heads_fit.cc (`heads fit`)
void add_listen_command(CLI::App& app, int& exit_code);     // listen.cc or listen_unavailable.cc
void add_score_command(CLI::App& app, int& exit_code);      // score.cc
void add_stability_command(CLI::App& app, int& exit_code);  // stability.cc
void add_contact_command(CLI::App& app, int& exit_code);    // contact.cc
void add_record_command(CLI::App& app, int& exit_code);     // record.cc (with runtime/capture)
void add_replay_command(CLI::App& app, int& exit_code);     // listen.cc or listen_unavailable.cc
void add_strip_command(CLI::App& app, int& exit_code);      // strip.cc (with tools/boards)
void add_flash_command(CLI::App& app, int& exit_code);      // flash.cc (with tools/boards)

}  // namespace tlvlink::cli
