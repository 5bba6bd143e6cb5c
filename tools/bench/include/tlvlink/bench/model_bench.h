#pragma once
// `tlvlink bench` as a library call: load a model and create its executor (timed: `init`), fill
// graph input 0 (a preprocessed synthetic frame when the model has an input spec, else its first
// golden input, else zeros; other inputs zero), time the first inference, then `runs` single
// inferences after `warmup` untimed ones (timing.h). Also MACs, GMAC/s at the median and the
// process's peak RSS.
//
//   auto r = bench_model("enc.tlvm", {.executor = ExecutorKind::kXnnpack, .threads = 2});
//   std::fputs(bench_text(*r).c_str(), stdout);

#include <string>

#include <nlohmann/json.hpp>

#include "tlvlink/bench/timing.h"
#include "tlvlink/error.h"
#include "tlvlink/executor.h"

namespace tlvlink::bench {

struct BenchOptions {
  ExecutorKind executor = ExecutorKind::kXnnpack;
  int threads = 1;
  int runs = 50;   // >= 1
  int warmup = 5;  // >= 0
};

struct BenchResult {
  std::string model_path, model_name;
  ExecutorKind executor = ExecutorKind::kXnnpack;
  int threads = 1, runs = 0, warmup = 0;
  double load_ms = 0, init_ms = 0, first_ms = 0;  // init = load + executor creation
  LatencyStats latency;
  double mmac = 0, gmac_per_s = 0, peak_rss_mib = 0;
};

// Errors: the model does not load, the executor cannot be created (context "creating the
// <kind> executor"), an inference fails.
Result<BenchResult> bench_model(const std::string& model_path, const BenchOptions& options);

// The lines `tlvlink bench` prints, and its --json object.
std::string bench_text(const BenchResult& result);
nlohmann::json bench_json(const BenchResult& result);

}  // namespace tlvlink::bench
