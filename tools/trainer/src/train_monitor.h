#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "train_monitor.h is internal to tools/trainer: include its public headers instead"
#endif
// Progress and the JSON-lines log of a training phase. On a terminal the line
//   student  step 1200/4800 25%  loss 2.314  beta 0.63  T 0.052  lr 1.9e-04  41.3 samples/s  ETA
//   6m12s
// is redrawn in place (at most kProgressRedrawHz; tools/io/progress.h decides whether stderr is
// interactive); in both modes one line per epoch is printed, so CI logs stay short. Every step
// goes to the log:
//   {"phase":"student","step":1200,"epoch":3,"loss":2.314,"beta":0.63,"temperature":0.052,
//    "lr":0.00019,"samples_per_s":41.3}

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace tlvlink::trainer {

class TrainMonitor {
 public:
  // `log` may be null (no log); it is borrowed for the monitor's lifetime.
  TrainMonitor(std::string phase, int64_t start_step, int64_t total_steps, int64_t batch,
               std::FILE* log);
  TrainMonitor(const TrainMonitor&) = delete;
  TrainMonitor& operator=(const TrainMonitor&) = delete;
  ~TrainMonitor();

  void step(int64_t step, int64_t epoch, double loss, double beta, double temperature, double lr);
  void epoch_end(int64_t epoch, int64_t epochs, double mean_loss);
  void finish();
  // Samples per second over the steps this monitor saw (0 before the first).
  double samples_per_s() const;
  double elapsed_s() const;

 private:
  void draw(int64_t step, double loss, double beta, double temperature, double lr);
  double now() const;

  std::string phase_;
  int64_t start_step_, total_steps_, batch_;
  std::FILE* log_;
  bool interactive_;
  std::chrono::steady_clock::time_point start_;
  double last_draw_ = -1;
  int64_t steps_seen_ = 0;
  double last_beta_ = 0, last_temperature_ = 0;
  bool finished_ = false;
};

}  // namespace tlvlink::trainer
