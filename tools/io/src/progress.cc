#include "tlvlink/io/progress.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace tlvlink::tools {
namespace {

double steady_seconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

bool ci_set() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && (std::strcmp(ci, "true") == 0 || std::strcmp(ci, "1") == 0);
}

std::string format_rate(double rate) {
  char buf[32];
  // Thresholds sit where "%.1f" would round up to the next format (99.96 -> "100/s").
  std::snprintf(buf, sizeof buf, rate >= 99.95 ? "%.0f/s" : "%.1f/s", rate);
  return buf;
}

}  // namespace

ProgressFigures progress_figures(int64_t done, int64_t total, double elapsed_s) {
  ProgressFigures f;
  if (total > 0)
    f.fraction = std::clamp(static_cast<double>(done) / static_cast<double>(total), 0.0, 1.0);
  if (elapsed_s > 0 && std::isfinite(elapsed_s) && done > 0) {
    f.rate_per_s = static_cast<double>(done) / elapsed_s;
    if (total > 0) f.eta_s = static_cast<double>(std::max<int64_t>(total - done, 0)) / f.rate_per_s;
  }
  return f;
}

std::string format_duration(double seconds) {
  if (!(seconds >= 0) || !std::isfinite(seconds)) return "--";
  char buf[32];
  if (seconds < 9.95) {
    std::snprintf(buf, sizeof buf, "%.1fs", seconds);
  } else if (seconds < 59.5) {
    std::snprintf(buf, sizeof buf, "%.0fs", seconds);
  } else if (seconds < 3599.5) {
    const auto s = static_cast<int64_t>(std::lround(seconds));
    std::snprintf(buf, sizeof buf, "%lldm%02llds", static_cast<long long>(s / 60),
                  static_cast<long long>(s % 60));
  } else {
    const auto m = static_cast<int64_t>(std::lround(seconds / 60));
    std::snprintf(buf, sizeof buf, "%lldh%02lldm", static_cast<long long>(m / 60),
                  static_cast<long long>(m % 60));
  }
  return buf;
}

bool progress_is_interactive(std::FILE* out) {
  return out != nullptr && isatty(fileno(out)) == 1 && !ci_set();
}

Progress::Progress(std::string label, int64_t total, std::FILE* out, ProgressMode mode, Clock clock)
    : label_(std::move(label)),
      total_(total),
      out_(out),
      interactive_(mode == ProgressMode::kInteractive ||
                   (mode == ProgressMode::kAuto && progress_is_interactive(out))),
      clock_(clock ? std::move(clock) : Clock(steady_seconds)) {
  start_ = clock_();
}

void Progress::set(int64_t done) {
  done_ = done;
  if (!interactive_ || finished_) return;
  const double now = clock_();
  // The first call draws at once; later ones at most kProgressRedrawHz times a second.
  if (last_draw_ >= 0 && now - last_draw_ < 1.0 / kProgressRedrawHz && done_ != total_) return;
  draw(now);
}

void Progress::draw(double now) {
  last_draw_ = now;
  ++redraws_;
  const ProgressFigures f = progress_figures(done_, total_, now - start_);
  // \r returns to the line start, \x1b[K clears what a longer previous line left behind.
  std::fprintf(out_, "\r%s %lld/%lld (%.1f%%)  %s  ETA %s\x1b[K", label_.c_str(),
               static_cast<long long>(done_), static_cast<long long>(total_), 100.0 * f.fraction,
               format_rate(f.rate_per_s).c_str(), format_duration(f.eta_s).c_str());
  std::fflush(out_);
}

void Progress::finish(std::string_view extra) {
  if (finished_) return;
  finished_ = true;
  const double elapsed = clock_() - start_;
  const ProgressFigures f = progress_figures(done_, total_, elapsed);
  if (interactive_ && redraws_ > 0) std::fputs("\r\x1b[K", out_);
  std::fprintf(out_, "%s: %lld/%lld in %s (%s)%s%.*s\n", label_.c_str(),
               static_cast<long long>(done_), static_cast<long long>(total_),
               format_duration(elapsed).c_str(), format_rate(f.rate_per_s).c_str(),
               extra.empty() ? "" : ", ", static_cast<int>(extra.size()), extra.data());
  std::fflush(out_);
}

}  // namespace tlvlink::tools
