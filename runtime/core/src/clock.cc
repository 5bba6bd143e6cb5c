#include "tlvlink/clock.h"

#include <ctime>

namespace tlvlink {
namespace {

std::atomic<FakeClock*> g_fake{nullptr};

}  // namespace

int64_t board_clock_ns() {
  if (const FakeClock* fake = g_fake.load(std::memory_order_acquire)) return fake->now_ns();
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * kNsPerS + ts.tv_nsec;
}

void sleep_until_ns(int64_t when_ns) {
  if (FakeClock* fake = g_fake.load(std::memory_order_acquire)) {
    fake->advance_to(when_ns);
    return;
  }
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(when_ns / kNsPerS);
  ts.tv_nsec = static_cast<long>(when_ns % kNsPerS);
  ::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
}

FakeClock::FakeClock(int64_t start_ns) : now_(start_ns) {
  g_fake.store(this, std::memory_order_release);
}

FakeClock::~FakeClock() {
  FakeClock* self = this;
  g_fake.compare_exchange_strong(self, nullptr, std::memory_order_acq_rel);
}

void FakeClock::advance_to(int64_t when_ns) {
  int64_t now = now_.load(std::memory_order_acquire);
  while (when_ns > now && !now_.compare_exchange_weak(now, when_ns, std::memory_order_acq_rel)) {
  }
}

}  // namespace tlvlink
