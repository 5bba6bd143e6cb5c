// bench_model: `tlvlink bench` (model_bench.h).

#include "tlvlink/bench/model_bench.h"

#include <cstring>
#include <memory>
#include <vector>

#include "tlvlink/inspect/graph_stats.h"
#include "tlvlink/io/format.h"
#include "tlvlink/io/model_file.h"
#include "tlvlink/quantize/frames.h"

namespace tlvlink::bench {
namespace {

// Graph input 0: a preprocessed synthetic frame when the model has an input spec, else the
// first golden input, else zeros.
Status fill_input(const Model& m, std::span<std::byte> dst) {
  const Tensor& in = m.graph().tensor(m.graph().inputs[0]);
  if (in.dtype == DType::kFloat32 && m.metadata().input.height > 0) {
    TLV_ASSIGN_OR_RETURN(std::vector<float> x, quantize::synthetic_input(m, 7));
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

}  // namespace

Result<BenchResult> bench_model(const std::string& model_path, const BenchOptions& o) {
  BenchResult r;
  r.model_path = model_path;
  r.executor = o.executor;
  r.threads = o.threads;
  r.runs = o.runs;
  r.warmup = o.warmup;
  TLV_ENSURE(o.runs >= 1 && o.warmup >= 0, ErrorCode::kInvalidArgument,
             "runs %d must be >= 1 and warm-up %d >= 0", o.runs, o.warmup);
  const auto t_init = Clock::now();
  TLV_ASSIGN_OR_RETURN(const std::unique_ptr<Model> model, tools::load_model(model_path));
  r.load_ms = ms_since(t_init);
  const Model& m = *model;
  ExecutorOptions eo;
  eo.threads = o.threads;
  auto exec = make_executor(m, o.executor, eo);
  if (!exec.ok())
    return exec.error().with_context("creating the %s executor", executor_kind_name(o.executor));
  r.init_ms = ms_since(t_init);
  Executor& e = **exec;
  r.executor = e.kind();
  r.model_name = std::string(m.metadata().name);
  for (size_t i = 0; i < m.graph().inputs.size(); ++i) {
    if (i == 0) {
      TLV_TRY(fill_input(m, e.input(0)));
    } else {
      std::memset(e.input(i).data(), 0, e.input(i).size());
    }
  }
  TLV_ASSIGN_OR_RETURN(r.first_ms, time_invoke(e));
  TLV_TRY(warm_up(e, o.warmup));
  std::vector<double> samples;
  TLV_TRY(time_runs(e, o.runs, samples));
  r.latency = latency_stats(std::move(samples));
  r.mmac = static_cast<double>(inspect::graph_stats(m.graph()).macs) / 1e6;
  r.gmac_per_s = r.mmac / r.latency.median;  // MMAC per ms == GMAC/s
  r.peak_rss_mib = peak_rss_mib();
  return r;
}

std::string bench_text(const BenchResult& r) {
  std::string s;
  tools::appendf(s, "model     %s (%s), %.2f MMAC\n", r.model_path.c_str(), r.model_name.c_str(),
                 r.mmac);
  tools::appendf(s, "executor  %s, %d thread(s)\n", executor_kind_name(r.executor), r.threads);
  tools::appendf(s, "init      %.3f ms (load %.3f ms + create %.3f ms)\n", r.init_ms, r.load_ms,
                 r.init_ms - r.load_ms);
  tools::appendf(s, "first     %.3f ms\n", r.first_ms);
  tools::appendf(
      s,
      "runs      %d after %d warm-up: median %.3f ms, p90 %.3f ms, p99 %.3f ms (min %.3f, max "
      "%.3f)\n",
      r.runs, r.warmup, r.latency.median, r.latency.p90, r.latency.p99, r.latency.min,
      r.latency.max);
  tools::appendf(s, "speed     %.2f GMAC/s at the median\n", r.gmac_per_s);
  tools::appendf(s, "peak RSS  %.1f MiB\n", r.peak_rss_mib);
  return s;
}

nlohmann::json bench_json(const BenchResult& r) {
  return {{"model", r.model_path},
          {"name", r.model_name},
          {"executor", executor_kind_name(r.executor)},
          {"threads", r.threads},
          {"runs", r.runs},
          {"warmup", r.warmup},
          {"load_ms", r.load_ms},
          {"init_ms", r.init_ms},
          {"first_ms", r.first_ms},
          {"median_ms", r.latency.median},
          {"p90_ms", r.latency.p90},
          {"p99_ms", r.latency.p99},
          {"min_ms", r.latency.min},
          {"max_ms", r.latency.max},
          {"mmac", r.mmac},
          {"gmac_per_s", r.gmac_per_s},
          {"peak_rss_mib", r.peak_rss_mib}};
}

}  // namespace tlvlink::bench
