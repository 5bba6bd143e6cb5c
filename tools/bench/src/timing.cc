// The timing harness (timing.h).

#include "tlvlink/bench/timing.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace tlvlink::bench {

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double percentile(std::span<const double> sorted, double p) {
  const auto rank = static_cast<size_t>(std::ceil(p / 100.0 * static_cast<double>(sorted.size())));
  return sorted[std::clamp<size_t>(rank, 1, sorted.size()) - 1];
}

LatencyStats latency_stats(std::vector<double> samples) {
  std::sort(samples.begin(), samples.end());
  return LatencyStats{percentile(samples, 50), percentile(samples, 90), percentile(samples, 99),
                      samples.front(), samples.back()};
}

Result<double> time_invoke(Executor& executor) {
  const auto t0 = Clock::now();
  TLV_TRY(executor.invoke());
  return ms_since(t0);
}

Status warm_up(Executor& executor, int count) {
  for (int i = 0; i < count; ++i) TLV_TRY(executor.invoke());
  return {};
}

Status time_runs(Executor& executor, int runs, std::vector<double>& samples_ms) {
  samples_ms.reserve(samples_ms.size() + static_cast<size_t>(std::max(runs, 0)));
  for (int i = 0; i < runs; ++i) {
    TLV_ASSIGN_OR_RETURN(const double ms, time_invoke(executor));
    samples_ms.push_back(ms);
  }
  return {};
}

Status time_interleaved(std::span<TimedExecutor> timed, int runs, int per_block) {
  TLV_ENSURE(per_block >= 1, ErrorCode::kInvalidArgument, "per_block %d < 1", per_block);
  for (int done = 0; done < runs; done += per_block) {
    const int block = std::min(per_block, runs - done);
    for (TimedExecutor& t : timed) {
      TLV_TRY(t.executor->invoke());
      TLV_TRY(time_runs(*t.executor, block, t.samples_ms));
    }
  }
  return {};
}

double load_average_1min() {
  double load = 0;
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = 0;
    std::fclose(f);
  }
  return load;
}

double peak_rss_mib() {
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace tlvlink::bench
