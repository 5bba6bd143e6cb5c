#pragma once
// What went wrong while loading a dataset, item by item. Loaders do not stop at a missing or
// corrupt file or a malformed line: they skip the item, count it here, keep the first few
// problems in full (path, line, reason) and hand every problem to an optional callback.

#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "tlvlink/atomic_file.h"
#include "tlvlink/error.h"

namespace tlvlink::datasets {

enum class ProblemKind : uint8_t {
  kMissingFile,      // a file the index names does not exist
  kCorruptFile,      // it exists but cannot be decoded (JPEG, HDF5, wrong size/shape)
  kMalformedLine,    // a label / JSON line that does not parse or has bad values
  kMalformedRecord,  // an HDF5 grasp record without the documented keys
  kSidecarMismatch,  // tlvlink_sim_*.jsonl out of step with the index (metadata dropped)
};
const char* problem_kind_name(ProblemKind kind);  // "missing file", ...

struct LoadProblem {
  ProblemKind kind = ProblemKind::kMissingFile;
  std::string path;  // the file at fault
  int64_t line = 0;  // 1-based line in `path` for line problems, else 0
  std::string reason;
  std::string to_string() const;  // "path:line: kind: reason"
};

class LoadReport {
 public:
  // Keeps the first `max_kept` problems in problems(); counts all of them.
  explicit LoadReport(size_t max_kept = 100) : max_kept_(max_kept) {}

  void add(LoadProblem problem);
  void count_loaded() { ++loaded_; }

  int64_t loaded() const { return loaded_; }
  int64_t count(ProblemKind kind) const { return counts_[static_cast<size_t>(kind)]; }
  int64_t missing_files() const { return count(ProblemKind::kMissingFile); }
  int64_t corrupt_files() const { return count(ProblemKind::kCorruptFile); }
  int64_t malformed_lines() const { return count(ProblemKind::kMalformedLine); }
  int64_t problem_count() const;
  const std::vector<LoadProblem>& problems() const { return problems_; }

  // Called with every problem as it is met (e.g. the CLI prints them to stderr).
  std::function<void(const LoadProblem&)> on_problem;

  // "1234 loaded; 3 missing files, 1 corrupt file, 2 malformed lines" (only non-zero counts).
  std::string summary() const;

 private:
  static constexpr size_t kKinds = 5;
  size_t max_kept_;
  int64_t loaded_ = 0;
  int64_t counts_[kKinds] = {};
  std::vector<LoadProblem> problems_;
};

// What a command shows of the problems met while loading (one object per run, shared by every
// loader of the run): each of the first `shown` problems on `out` as it is met, "PREFIX:
// path:line: kind: reason"; with a `log_path`, every problem also goes to that file (replaced
// atomically at finish()). Install on a loader with `report.on_problem = echo.callback()`.
class ProblemEcho {
 public:
  ProblemEcho(std::string prefix, std::FILE* out, size_t shown = 10, std::string log_path = {});
  // `index_lines` false: skip malformed lines (a second pass over an index already reported).
  std::function<void(const LoadProblem&)> callback(bool index_lines = true);
  // Prints "PREFIX: N load problems (the first K above), all in PATH" and commits the log; a
  // failed log write is the error. Without a log_path, more problems than `shown` go to
  // $TMPDIR/PREFIX-problems-PID.txt (all of them), so none is only counted.
  Status finish();
  size_t seen() const { return seen_; }

 private:
  void add(const LoadProblem& p);
  std::string prefix_;
  std::FILE* out_;
  size_t shown_;
  std::string log_path_;            // --problems FILE, or our own file once past shown_
  std::vector<std::string> first_;  // the lines shown, until a file is opened for them
  std::optional<AtomicFile> log_;
  Status log_status_;
  size_t seen_ = 0;
};

}  // namespace tlvlink::datasets
