#include "common.h"

#include <cstdio>

#include "tlvlink/io/model_file.h"

namespace tlvlink::cli {

int exit_code_of(const Error& error) {
  return error.code() == ErrorCode::kInvalidArgument ? kExitUsage : kExitFailure;
}

int report_error(const char* command, const Error& error) {
  std::fprintf(stderr, "tlvlink %s: error [%s]: %s\n", command, error_code_name(error.code()),
               error.message());
  return exit_code_of(error);
}

Result<std::unique_ptr<Model>> load_model(const std::string& path) {
  return tools::load_model(path);
}

void ExecutorFlags::add_to(CLI::App& app, const char* threads_help) {
  app.add_option("--executor,-e", executor, "Executor: xnnpack (default) or reference")
      ->check(CLI::IsMember({"xnnpack", "reference"}))
      ->capture_default_str();
  app.add_option("--threads,-t", threads,
                 threads_help != nullptr ? threads_help
                                         : "Threads for the XNNPACK thread pool (reference "
                                           "ignores it)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
}

ExecutorKind ExecutorFlags::kind() const {
  auto kind = parse_executor_kind(executor);
  return kind.ok() ? *kind : ExecutorKind::kXnnpack;
}

ExecutorOptions ExecutorFlags::options() const {
  ExecutorOptions o;
  o.threads = threads;
  return o;
}

Result<std::unique_ptr<Executor>> create_executor(const Model& model, const ExecutorFlags& flags) {
  TLV_ASSIGN_OR_RETURN(ExecutorKind kind, parse_executor_kind(flags.executor));
  auto exec = make_executor(model, kind, flags.options());
  if (!exec.ok())
    return exec.error().with_context("creating the %s executor", flags.executor.c_str());
  return std::move(exec).value();
}

}  // namespace tlvlink::cli
