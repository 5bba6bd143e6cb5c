#include "train_monitor.h"

#include "tlvlink/io/progress.h"

namespace tlvlink::trainer {

TrainMonitor::TrainMonitor(std::string phase, int64_t start_step, int64_t total_steps,
                           int64_t batch, std::FILE* log)
    : phase_(std::move(phase)),
      start_step_(start_step),
      total_steps_(total_steps),
      batch_(batch),
      log_(log),
      interactive_(tools::progress_is_interactive(stderr)),
      start_(std::chrono::steady_clock::now()) {}

TrainMonitor::~TrainMonitor() { finish(); }

double TrainMonitor::now() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

double TrainMonitor::elapsed_s() const { return now(); }

double TrainMonitor::samples_per_s() const {
  const double t = now();
  return t > 0 ? static_cast<double>(steps_seen_ * batch_) / t : 0.0;
}

void TrainMonitor::step(int64_t step, int64_t epoch, double loss, double beta, double temperature,
                        double lr) {
  ++steps_seen_;
  last_beta_ = beta;
  last_temperature_ = temperature;
  if (log_ != nullptr) {
    std::fprintf(log_,
                 "{\"phase\":\"%s\",\"step\":%lld,\"epoch\":%lld,\"loss\":%.6g,\"beta\":%.6g,"
                 "\"temperature\":%.6g,\"lr\":%.6g,\"samples_per_s\":%.4g}\n",
                 phase_.c_str(), static_cast<long long>(step), static_cast<long long>(epoch), loss,
                 beta, temperature, lr, samples_per_s());
  }
  const double t = now();
  if (interactive_ && (last_draw_ < 0 || t - last_draw_ >= 1.0 / tools::kProgressRedrawHz)) {
    last_draw_ = t;
    draw(step, loss, beta, temperature, lr);
  }
}

void TrainMonitor::draw(int64_t step, double loss, double beta, double temperature, double lr) {
  const tools::ProgressFigures f =
      tools::progress_figures(step + 1 - start_step_, total_steps_ - start_step_, now());
  std::fprintf(stderr,
               "\r%s  step %lld/%lld %3.0f%%  loss %.3f  beta %.2f  T %.3f  lr %.1e  %.1f "
               "samples/s  ETA %s\x1b[K",
               phase_.c_str(), static_cast<long long>(step + 1),
               static_cast<long long>(total_steps_),
               100.0 * static_cast<double>(step + 1) / static_cast<double>(total_steps_), loss,
               beta, temperature, lr, samples_per_s(), tools::format_duration(f.eta_s).c_str());
  std::fflush(stderr);
}

void TrainMonitor::epoch_end(int64_t epoch, int64_t epochs, double mean_loss) {
  if (log_ != nullptr) std::fflush(log_);
  if (interactive_) std::fputs("\r\x1b[K", stderr);  // the epoch line replaces the progress line
  const double t = now();
  const int64_t remaining = total_steps_ - start_step_ - steps_seen_;
  const double eta =
      steps_seen_ > 0 ? t * static_cast<double>(remaining) / static_cast<double>(steps_seen_) : -1;
  std::fprintf(stderr,
               "%s epoch %lld/%lld: mean loss %.4f, beta %.3f, T %.4f, %.1f samples/s, "
               "elapsed %s, ETA %s\n",
               phase_.c_str(), static_cast<long long>(epoch + 1), static_cast<long long>(epochs),
               mean_loss, last_beta_, last_temperature_, samples_per_s(),
               tools::format_duration(t).c_str(), tools::format_duration(eta).c_str());
}

void TrainMonitor::finish() {
  if (finished_) return;
  finished_ = true;
  if (log_ != nullptr) std::fflush(log_);
  if (interactive_ && last_draw_ >= 0) std::fputc('\n', stderr);
}

}  // namespace tlvlink::trainer
