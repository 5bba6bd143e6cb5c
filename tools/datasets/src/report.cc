#include "tlvlink/datasets/report.h"

#include <cstdio>

namespace tlvlink::datasets {

const char* problem_kind_name(ProblemKind kind) {
  switch (kind) {
    case ProblemKind::kMissingFile: return "missing file";
    case ProblemKind::kCorruptFile: return "corrupt file";
    case ProblemKind::kMalformedLine: return "malformed line";
    case ProblemKind::kMalformedRecord: return "malformed record";
    case ProblemKind::kSidecarMismatch: return "sidecar mismatch";
  }
  return "problem";
}

std::string LoadProblem::to_string() const {
  std::string s = path;
  if (line > 0) s += ":" + std::to_string(line);
  s += ": ";
  s += problem_kind_name(kind);
  if (!reason.empty()) s += ": " + reason;
  return s;
}

void LoadReport::add(LoadProblem problem) {
  ++counts_[static_cast<size_t>(problem.kind)];
  if (on_problem) on_problem(problem);
  if (problems_.size() < max_kept_) problems_.push_back(std::move(problem));
}

int64_t LoadReport::problem_count() const {
  int64_t n = 0;
  for (int64_t c : counts_) n += c;
  return n;
}

std::string LoadReport::summary() const {
  std::string s = std::to_string(loaded_) + " loaded";
  const char* sep = "; ";
  for (size_t k = 0; k < kKinds; ++k) {
    if (counts_[k] == 0) continue;
    s += sep;
    sep = ", ";
    s += std::to_string(counts_[k]) + " " + problem_kind_name(static_cast<ProblemKind>(k));
    if (counts_[k] != 1) s += "s";
  }
  if (problem_count() == 0) s += "; no problems";
  return s;
}

std::function<void(const LoadProblem&)> ProblemEcho::callback() {
  return [this](const LoadProblem& p) {
    if (seen_++ < shown_) std::fprintf(out_, "%s: %s\n", prefix_.c_str(), p.to_string().c_str());
  };
}

void ProblemEcho::finish() {
  if (seen_ > shown_) {
    std::fprintf(out_, "%s: ... and %zu more problems not shown\n", prefix_.c_str(),
                 seen_ - shown_);
  }
  seen_ = 0;
}

}  // namespace tlvlink::datasets
