// A board program on the minimal runtime (tests/minimal): links tlvlink_runtime and
// tlvlink_verify alone, built without exceptions like target code, and runs every golden pair of
// each model given on every executor this build has, with the tolerances of `tlvlink verify`
// (runtime/verify). Without XNNPACK, asking for it must be a clear error, not a crash.
//   tlvlink_board_smoke MODEL.tlvm...      exit 0: all pairs within tolerance
#include <cstdio>

#include "tlvlink/tlvlink.h"
#include "tlvlink/verify/golden.h"

namespace {

using namespace tlvlink;

// Runs the model's golden pairs and head outputs on `exec`; returns the number of failures.
int run_pairs(const char* path, const Model& model, Executor& exec) {
  auto report = verify::verify_golden(model, exec);
  if (!report.ok()) {
    std::printf("%s %s: %s\n", path, executor_kind_name(exec.kind()), report.error().message());
    return 1;
  }
  int failures = 0;
  for (const verify::PairResult& p : report->pairs) {
    const verify::OutputComparison& c = p.comparison;
    failures += c.pass ? 0 : 1;
    std::printf("%s %s pair %zu: max abs error %.4g (allowed %.4g: %s) %s\n", path,
                executor_kind_name(exec.kind()), p.index, c.max_abs_error, c.tolerance, c.rule,
                c.pass ? "PASS" : "FAIL");
  }
  // The shipped models store their heads' outputs too: the board checks its head arithmetic.
  const verify::HeadCheck& h = report->heads;
  failures += h.stored && h.pass ? 0 : 1;
  std::printf("%s %s golden head outputs: %s, max abs error %.4g (allowed %.4g) %s\n", path,
              executor_kind_name(exec.kind()), h.stored ? "stored" : "NOT STORED", h.max_abs_error,
              h.tolerance, h.stored && h.pass ? "PASS" : "FAIL");
  return failures;
}

int check_model(const char* path) {
  auto model = Model::load_file(path);
  if (!model.ok()) {
    std::printf("%s: %s\n", path, model.error().message());
    return 1;
  }
  const Model& m = **model;
  if (m.metadata().golden.empty()) {
    std::printf("%s: no golden pairs\n", path);
    return 1;
  }
  int failures = 0;
  for (ExecutorKind kind : {ExecutorKind::kReference, ExecutorKind::kXnnpack}) {
    auto exec = make_executor(m, kind, {.threads = 2});
#if defined(TLVLINK_HAVE_XNNPACK)
    constexpr bool kHaveXnnpack = true;
#else
    constexpr bool kHaveXnnpack = false;
#endif
    if (kind == ExecutorKind::kXnnpack && !kHaveXnnpack) {
      const bool clear = !exec.ok() && exec.error().code() == ErrorCode::kModelUnsupported;
      std::printf("%s xnnpack: %s (%s)\n", path, clear ? "unavailable as expected" : "FAIL",
                  exec.ok() ? "created in a build without XNNPACK" : exec.error().message());
      failures += clear ? 0 : 1;
      continue;
    }
    if (!exec.ok()) {
      std::printf("%s %s: %s\n", path, executor_kind_name(kind), exec.error().message());
      ++failures;
      continue;
    }
    failures += run_pairs(path, m, **exec);
  }
  return failures;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MODEL.tlvm...\n", argv[0]);
    return 2;
  }
  int failures = 0;
  for (int i = 1; i < argc; ++i) failures += check_model(argv[i]);
  std::printf("board smoke: %s\n", failures == 0 ? "PASS" : "FAIL");
  return failures == 0 ? 0 : 1;
}
