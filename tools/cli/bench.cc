// tlvlink bench MODEL: flags -> bench::bench_model (tools/bench: init time, first inference,
// median / p90 / p99 over N runs, MMAC and GMAC/s, peak RSS) -> text or JSON.

#include <cstdio>

#include "common.h"
#include "tlvlink/bench/model_bench.h"

namespace tlvlink::cli {
namespace {

struct BenchFlags {
  std::string model;
  ExecutorFlags exec;
  int runs = 50;
  int warmup = 5;
  bool json = false;
};

int run_bench(const BenchFlags& f) {
  bench::BenchOptions o;
  o.executor = f.exec.kind();
  o.threads = f.exec.threads;
  o.runs = f.runs;
  o.warmup = f.warmup;
  auto r = bench::bench_model(f.model, o);
  if (!r.ok()) return report_error("bench", r.error());
  if (f.json) {
    std::printf("%s\n", bench::bench_json(*r).dump(2).c_str());
  } else {
    std::fputs(bench::bench_text(*r).c_str(), stdout);
  }
  return kExitOk;
}

}  // namespace

void add_bench_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<BenchFlags>();
  CLI::App* cmd =
      app.add_subcommand("bench", "Time init, the first inference and N steady-state inferences");
  cmd->add_option("model", o->model, "Model file (.tlvm)")->required();
  o->exec.add_to(*cmd);
  cmd->add_option("--runs,-n", o->runs, "Timed inferences")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--warmup,-w", o->warmup, "Untimed inferences after the first")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Print machine-readable JSON");
  cmd->footer(kExitCodeFooter);
  cmd->callback([o, &exit_code] { exit_code = run_bench(*o); });
}

}  // namespace tlvlink::cli
