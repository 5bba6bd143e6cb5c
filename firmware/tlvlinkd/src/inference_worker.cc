#include "inference_worker.h"

#include <chrono>
#include <climits>
#include <cstdio>

#include "clock.h"
#include "tlvlink/log.h"

namespace tlvlink::daemon::internal {
namespace {

TLV_LOG_CATEGORY(kLogInference, "inference");
constexpr int32_t kWaitMs = 50;        // wake at least this often: stop flag, grasp timeouts
constexpr int32_t kFramesPerTurn = 8;  // then commands, grasp timing and counters get their turn

}  // namespace

InferenceWorker::InferenceWorker(pipeline::FrameProcessor& processor, std::vector<FrameRing*> rings,
                                 std::vector<pipeline::SensorSetup> setups, Doorbell& doorbell,
                                 OutputQueue& output, CommandQueue& commands,
                                 const std::atomic<bool>& stop, std::atomic<bool>& limit_hit,
                                 int64_t max_frames, std::vector<ScriptedCommand> script)
    : processor_(processor),
      rings_(std::move(rings)),
      setups_(std::move(setups)),
      doorbell_(doorbell),
      output_(output),
      commands_(commands),
      script_(std::move(script)),
      stop_(stop),
      limit_hit_(limit_hit),
      max_frames_(max_frames) {}

void InferenceWorker::apply(const Command& c) {
  switch (c.kind) {
    case CommandKind::kRezero: processor_.rezero(c.sensor); break;
    case CommandKind::kClosed: processor_.mark_closed(c.t_ns); break;
    case CommandKind::kLifting: processor_.mark_lifting(c.t_ns); break;
  }
}

void InferenceWorker::drain_grasps() {
  pipeline::GraspPrediction g;
  while (processor_.take_grasp(g)) output_.push(g);
}

bool InferenceWorker::process_one() {
  size_t best = rings_.size();
  int64_t best_t = INT64_MAX;
  for (size_t i = 0; i < rings_.size(); ++i) {
    const int64_t t = rings_[i]->oldest_capture_ns();
    if (t < best_t) {
      best_t = t;
      best = i;
    }
  }
  if (best == rings_.size()) return false;
  DecodedFrame* f = rings_[best]->take();
  if (f == nullptr) return false;
  // A scripted mark of this sensor due at this frame is given first, at the frame's capture time.
  while (next_scripted_ < script_.size() &&
         script_[next_scripted_].sensor == static_cast<int32_t>(best) &&
         f->sequence >= script_[next_scripted_].sequence) {
    apply(Command{script_[next_scripted_].kind, f->times.capture_ns, -1});
    ++next_scripted_;
  }
  // The processed frame's geometry is the ring's; the processor checks it against its plan.
  const pipeline::SensorSetup& s = setups_[best];
  const Status st =
      processor_.process(static_cast<int32_t>(best), f->sequence,
                         {f->rgb.data(), s.width, s.height, s.channels, 0}, f->times, record_);
  if (!st.ok()) {
    rings_[best]->recycle(f);
    errors_.fetch_add(1);
    EventRecord e;
    e.t_ns = board_clock_ns();
    e.sensor = static_cast<int32_t>(best);
    e.error = true;
    std::snprintf(e.text.data(), e.text.size(), "%s", st.error().message());
    TLV_LOG(kLogInference, kError, "%s", e.text.data());
    output_.push(e);
    return true;
  }
  output_.push(record_);
  // After the prediction is on its way: a due image is copied from the frame before it is recycled.
  if (images_ != nullptr) {
    images_->offer(
        static_cast<int32_t>(best), f->sequence, f->times.capture_ns,
        {f->rgb.data(), s.width, s.height, s.channels, 0},
        record_.contact_state != static_cast<uint8_t>(pipeline::ContactState::kNoContact));
  }
  rings_[best]->recycle(f);
  drain_grasps();
  return true;
}

void InferenceWorker::run() {
  cpu_clock_ = this_thread_cpu_clock();
  bool backlog = false;  // frames were left waiting at the end of the last turn
  for (;;) {
    {
      std::unique_lock lock(doorbell_.mutex);
      if (!backlog) {
        doorbell_.cv.wait_for(lock, std::chrono::milliseconds(kWaitMs),
                              [&] { return doorbell_.rings > 0 || stop_.load(); });
      }
      doorbell_.rings = 0;
    }
    Command c;
    while (commands_.pop(c)) apply(c);
    // A bounded turn: when the encoder is slower than the cameras there is always another frame,
    // and an unbounded loop would never apply commands, time grasps or publish the counters.
    backlog = false;
    for (int32_t n = 0; n < kFramesPerTurn; ++n) {
      if (!process_one()) break;
      if (max_frames_ > 0 && static_cast<int64_t>(processor_.counters().frames) >= max_frames_) {
        limit_hit_ = true;
      }
      backlog = n + 1 == kFramesPerTurn;
    }
    processor_.tick(board_clock_ns());
    drain_grasps();
    {
      std::lock_guard lock(mutex_);
      counters_ = processor_.counters();
    }
    // Stop only once the capture threads have stopped and every decoded frame is processed.
    if (stop_.load() && !backlog) break;
  }
  final_cpu_ns_ = thread_cpu_ns(cpu_clock_.load());
}

InferenceSnapshot InferenceWorker::snapshot() const {
  InferenceSnapshot s;
  {
    std::lock_guard lock(mutex_);
    s.counters = counters_;
  }
  s.errors = errors_.load();
  const clockid_t clock = cpu_clock_.load();
  const int64_t final_cpu = final_cpu_ns_.load();
  s.cpu_ns = final_cpu >= 0 ? final_cpu : clock == -1 ? 0 : thread_cpu_ns(clock);
  return s;
}

}  // namespace tlvlink::daemon::internal
