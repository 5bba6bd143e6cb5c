#pragma once
// The one timing harness of tlvlink's measurements (`tlvlink bench`, `quantize-sweep`): single
// inferences timed with steady_clock, nearest-rank percentiles, and interleaved timing of several
// executors so a burst of load on a shared machine hits every variant alike.
//
//   TLV_ASSIGN_OR_RETURN(double first_ms, time_invoke(exec));   // the first inference
//   TLV_TRY(warm_up(exec, 5));
//   std::vector<double> ms;
//   TLV_TRY(time_runs(exec, 50, ms));
//   const LatencyStats s = latency_stats(ms);                  // median, p90, p99, min, max

#include <chrono>
#include <cstddef>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/executor.h"

namespace tlvlink::bench {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0);

// Nearest-rank percentile (p in (0, 100]) of ascending `sorted`; precondition: not empty.
double percentile(std::span<const double> sorted, double p);

struct LatencyStats {
  double median = 0, p90 = 0, p99 = 0, min = 0, max = 0;  // ms
};
// Precondition: `samples` not empty.
LatencyStats latency_stats(std::vector<double> samples);

// One inference, timed (ms).
Result<double> time_invoke(Executor& executor);
// `count` untimed inferences.
Status warm_up(Executor& executor, int count);
// `runs` inferences, each timed on its own, appended to `samples_ms`.
Status time_runs(Executor& executor, int runs, std::vector<double>& samples_ms);

// Several executors timed together: per round, every executor gets one untimed inference (its
// thread pool wakes up) and then up to `per_block` timed ones, until each has `runs` samples. A
// multi-threaded pool stays warm within its block (one inference per turn would time the
// wake-up of a cold worker thread, not the inference).
inline constexpr int kTimedPerBlock = 10;
struct TimedExecutor {
  Executor* executor = nullptr;  // borrowed
  std::vector<double> samples_ms;
};
Status time_interleaved(std::span<TimedExecutor> timed, int runs, int per_block = kTimedPerBlock);

// The 1-minute load average (/proc/loadavg; 0 when unavailable): latency on a shared machine
// depends on it, so reports state it.
double load_average_1min();
// Peak resident set size of this process, MiB (getrusage).
double peak_rss_mib();

}  // namespace tlvlink::bench
