#pragma once
// Progress of a long run (dataset generation, loading): count/total, rate and ETA redrawn in
// place on a terminal, at most kProgressRedrawHz times a second; one summary line and nothing
// else when stderr is not a terminal or CI is set (logs stay readable). Not thread-safe: call
// from the thread that drives the run.

#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>

namespace tlvlink::tools {

inline constexpr double kProgressRedrawHz = 5.0;

// The arithmetic of one progress line (exposed for tests).
struct ProgressFigures {
  double fraction = 0;    // done / total, in [0, 1]; 0 when total <= 0
  double rate_per_s = 0;  // done / elapsed; 0 before any time has passed
  double eta_s = -1;      // (total - done) / rate; -1 while unknown (no rate yet or no total)
};
ProgressFigures progress_figures(int64_t done, int64_t total, double elapsed_s);

// "0.4s", "42s", "3m05s", "2h07m"; "--" for a negative (unknown) duration.
std::string format_duration(double seconds);

enum class ProgressMode : uint8_t {
  kAuto,         // interactive iff `out` is a terminal and CI is not "true"/"1"
  kInteractive,  // redraw in place
  kQuiet,        // summary line only
};
bool progress_is_interactive(std::FILE* out);

class Progress {
 public:
  using Clock = std::function<double()>;  // monotonic seconds; default steady_clock

  Progress(std::string label, int64_t total, std::FILE* out = stderr,
           ProgressMode mode = ProgressMode::kAuto, Clock clock = {});
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void set(int64_t done);
  void add(int64_t n = 1) { set(done_ + n); }
  // Ends the line: "<label>: <done>/<total> in <time> (<rate>/s)[, <extra>]". Idempotent.
  void finish(std::string_view extra = {});

  int64_t done() const { return done_; }
  bool interactive() const { return interactive_; }
  int64_t redraws() const { return redraws_; }

 private:
  void draw(double now);

  std::string label_;
  int64_t total_;
  std::FILE* out_;
  bool interactive_;
  Clock clock_;
  double start_ = 0, last_draw_ = -1;
  int64_t done_ = 0, redraws_ = 0;
  bool finished_ = false;
};

}  // namespace tlvlink::tools
