#include "tlvlink/datasets/report.h"

#include <unistd.h>

#include <cctype>
#include <cstdlib>

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

ProblemEcho::ProblemEcho(std::string prefix, std::FILE* out, size_t shown, std::string log_path)
    : prefix_(std::move(prefix)), out_(out), shown_(shown), log_path_(std::move(log_path)) {}

std::function<void(const LoadProblem&)> ProblemEcho::callback(bool index_lines) {
  return [this, index_lines](const LoadProblem& p) {
    if (index_lines || p.kind != ProblemKind::kMalformedLine) add(p);
  };
}

// Where the rest go when the user named no --problems file: a report file of our own, so no
// problem is ever only counted. Its name carries the pid: two runs never share one.
namespace {

std::string default_problems_path(const std::string& prefix) {
  const char* tmp = std::getenv("TMPDIR");
  std::string name;
  for (char c : prefix) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '-';
  return std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/" + name + "-problems-" +
         std::to_string(static_cast<long long>(getpid())) + ".txt";
}

}  // namespace

void ProblemEcho::add(const LoadProblem& p) {
  const std::string text = p.to_string();
  if (seen_++ < shown_) std::fprintf(out_, "%s: %s\n", prefix_.c_str(), text.c_str());
  if (log_path_.empty()) {
    // No file named: keep the lines shown (at most shown_) until there are more than that.
    if (seen_ <= shown_) {
      first_.push_back(text);
      return;
    }
    log_path_ = default_problems_path(prefix_);
  }
  if (!log_status_.ok()) return;
  if (!log_) {
    auto f = AtomicFile::create(log_path_.c_str());
    if (!f.ok()) {
      log_status_ = f.error();
      return;
    }
    log_.emplace(std::move(f).value());
    for (const std::string& earlier : first_) {
      const std::string line = earlier + "\n";
      log_status_ = log_->write(line.data(), line.size());
      if (!log_status_.ok()) return;
    }
    first_.clear();
  }
  const std::string line = text + "\n";
  log_status_ = log_->write(line.data(), line.size());
}

Status ProblemEcho::finish() {
  if (seen_ > 0 && !log_path_.empty()) {
    if (seen_ > shown_) {
      std::fprintf(out_, "%s: %zu load problems (the first %zu above), all in %s\n",
                   prefix_.c_str(), seen_, shown_, log_path_.c_str());
    } else {
      std::fprintf(out_, "%s: %zu load problems, all in %s\n", prefix_.c_str(), seen_,
                   log_path_.c_str());
    }
  }
  TLV_TRY(log_status_);
  if (log_) {
    Status s = log_->commit();
    log_.reset();
    return s;
  }
  return {};
}

}  // namespace tlvlink::datasets
