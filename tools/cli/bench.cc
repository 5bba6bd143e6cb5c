// tlvlink bench MODEL: init time, first inference, then median / p90 / p99 over N runs,
// MMAC and GMAC/s, peak RSS.

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <nlohmann/json.hpp>

#include "cli/common.h"
#include "cli/frame_source.h"
#include "cli/op_stats.h"

namespace tlvlink::cli {
namespace {

using Clock = std::chrono::steady_clock;

struct BenchOptions {
  std::string model;
  ExecutorFlags exec;
  int runs = 50;
  int warmup = 5;
  bool json = false;
};

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Nearest-rank percentile of sorted samples.
double percentile(const std::vector<double>& sorted, double p) {
  const auto rank = static_cast<size_t>(std::ceil(p / 100.0 * static_cast<double>(sorted.size())));
  return sorted[std::clamp<size_t>(rank, 1, sorted.size()) - 1];
}

// Graph input 0: a preprocessed synthetic frame when the model has an input spec, else the
// first golden input, else zeros.
Status fill_input(const Model& m, std::span<std::byte> dst) {
  const Tensor& in = m.graph().tensor(m.graph().inputs[0]);
  if (in.dtype == DType::kFloat32 && m.metadata().input.height > 0) {
    TLV_ASSIGN_OR_RETURN(std::vector<float> x, synthetic_input(m, 7));
    if (x.size() * sizeof(float) == dst.size()) {
      std::memcpy(dst.data(), x.data(), dst.size());
      return {};
    }
  }
  if (!m.metadata().golden.empty()) {
    std::memcpy(dst.data(), m.metadata().golden[0].input.data(), dst.size());
  } else {
    std::memset(dst.data(), 0, dst.size());
  }
  return {};
}

int run_bench(const BenchOptions& o) {
  const auto t_init = Clock::now();
  auto model = load_model(o.model);
  if (!model.ok()) return report_error("bench", model.error());
  const double load_ms = ms_since(t_init);
  const Model& m = **model;
  auto exec = create_executor(m, o.exec);
  if (!exec.ok()) return report_error("bench", exec.error());
  const double init_ms = ms_since(t_init);
  Executor& e = **exec;
  for (size_t i = 0; i < m.graph().inputs.size(); ++i) {
    if (i == 0) {
      if (Status s = fill_input(m, e.input(0)); !s.ok()) return report_error("bench", s.error());
    } else {
      std::memset(e.input(i).data(), 0, e.input(i).size());
    }
  }
  auto t = Clock::now();
  if (Status s = e.invoke(); !s.ok()) return report_error("bench", s.error());
  const double first_ms = ms_since(t);
  for (int i = 0; i < o.warmup; ++i) {
    if (Status s = e.invoke(); !s.ok()) return report_error("bench", s.error());
  }
  std::vector<double> samples;
  samples.reserve(static_cast<size_t>(o.runs));
  for (int i = 0; i < o.runs; ++i) {
    t = Clock::now();
    if (Status s = e.invoke(); !s.ok()) return report_error("bench", s.error());
    samples.push_back(ms_since(t));
  }
  std::sort(samples.begin(), samples.end());
  const double median = percentile(samples, 50), p90 = percentile(samples, 90),
               p99 = percentile(samples, 99);
  const double mmac = static_cast<double>(graph_stats(m.graph()).macs) / 1e6;
  const double gmacs = mmac / median;  // MMAC per ms == GMAC/s
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  const double rss_mb = static_cast<double>(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux

  if (o.json) {
    nlohmann::json j = {{"model", o.model},
                        {"name", m.metadata().name},
                        {"executor", executor_kind_name(e.kind())},
                        {"threads", o.exec.threads},
                        {"runs", o.runs},
                        {"warmup", o.warmup},
                        {"load_ms", load_ms},
                        {"init_ms", init_ms},
                        {"first_ms", first_ms},
                        {"median_ms", median},
                        {"p90_ms", p90},
                        {"p99_ms", p99},
                        {"min_ms", samples.front()},
                        {"max_ms", samples.back()},
                        {"mmac", mmac},
                        {"gmac_per_s", gmacs},
                        {"peak_rss_mib", rss_mb}};
    std::printf("%s\n", j.dump(2).c_str());
    return kExitOk;
  }
  std::printf("model     %s (%.*s), %.2f MMAC\n", o.model.c_str(),
              static_cast<int>(m.metadata().name.size()), m.metadata().name.data(), mmac);
  std::printf("executor  %s, %d thread(s)\n", executor_kind_name(e.kind()), o.exec.threads);
  std::printf("init      %.3f ms (load %.3f ms + create %.3f ms)\n", init_ms, load_ms,
              init_ms - load_ms);
  std::printf("first     %.3f ms\n", first_ms);
  std::printf(
      "runs      %d after %d warm-up: median %.3f ms, p90 %.3f ms, p99 %.3f ms (min %.3f, max "
      "%.3f)\n",
      o.runs, o.warmup, median, p90, p99, samples.front(), samples.back());
  std::printf("speed     %.2f GMAC/s at the median\n", gmacs);
  std::printf("peak RSS  %.1f MiB\n", rss_mb);
  return kExitOk;
}

}  // namespace

void add_bench_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<BenchOptions>();
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
