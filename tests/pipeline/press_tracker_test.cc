// The press tracker (runtime/pipeline press_tracker.h): at every frame of a contact its peak is
// the mean of the frames at most two either side of the first frame with the highest score so
// far, and its first frame the contact's first; restart() forgets a contact; add() allocates
// nothing. The reference below is the definition written the offline way (the whole sequence at
// once, as tools/eval/press_sequence.py computes it).
#include <algorithm>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "support/alloc_counter.h"
#include "tlvlink/pipeline/press_tracker.h"

namespace tlvlink::pipeline {
namespace {

constexpr int32_t kDim = 3;

// Mean of frames [k-2, k+2] of the first `n` frames, k the first maximum score among them.
std::vector<float> reference_peak(const std::vector<std::vector<float>>& e,
                                  const std::vector<float>& score, size_t n) {
  const size_t k = static_cast<size_t>(
      std::max_element(score.begin(), score.begin() + static_cast<std::ptrdiff_t>(n)) -
      score.begin());
  const size_t lo = k >= 2 ? k - 2 : 0, hi = std::min(n, k + 3);
  std::vector<float> mean(kDim, 0.0f);
  for (size_t j = lo; j < hi; ++j)
    for (size_t i = 0; i < kDim; ++i) mean[i] += e[j][i] / static_cast<float>(hi - lo);
  return mean;
}

TEST(PressTracker, PeakAndFirstFollowTheDefinitionAtEveryFrame) {
  std::mt19937 rng(29);
  std::uniform_real_distribution<float> u(-1, 1);
  std::uniform_int_distribution<int> level(0, 6);  // coarse scores: ties happen
  PressTracker t(kDim);
  for (int contact = 0; contact < 50; ++contact) {
    const size_t n = 1 + static_cast<size_t>(contact % 17);
    std::vector<std::vector<float>> e(n, std::vector<float>(kDim));
    std::vector<float> score(n);
    for (size_t j = 0; j < n; ++j) {
      for (float& v : e[j]) v = u(rng);
      score[j] = static_cast<float>(level(rng));
    }
    t.restart();
    for (size_t j = 0; j < n; ++j) {
      t.add(e[j], score[j]);
      EXPECT_EQ(t.frames(), static_cast<int32_t>(j + 1));
      EXPECT_EQ(t.ready(), j + 1 >= static_cast<size_t>(PressTracker::kMinFrames));
      const std::vector<float> want = reference_peak(e, score, j + 1);
      for (size_t i = 0; i < kDim; ++i) {
        // The tracker sums in double, the reference in float: a few ulp of values <= 1.
        EXPECT_NEAR(t.peak()[i], want[i], 1e-6) << "contact " << contact << " frame " << j;
        EXPECT_EQ(t.first()[i], e[0][i]);
      }
    }
  }
}

TEST(PressTracker, RestartForgetsTheLastContactAndAddAllocatesNothing) {
  PressTracker t(kDim);
  const std::vector<float> a = {1, 1, 1}, b = {3, 0, -3};
  for (int j = 0; j < 6; ++j) t.add(a, 10.0f);
  t.restart();
  EXPECT_EQ(t.frames(), 0);
  EXPECT_FALSE(t.ready());
  testing::start_counting_allocations();
  t.add(b, 1.0f);  // a lower score than the last contact's peak: still this contact's peak
  EXPECT_EQ(testing::stop_counting_allocations(), 0u);
  EXPECT_EQ(std::vector<float>(t.peak().begin(), t.peak().end()), b);
  EXPECT_EQ(std::vector<float>(t.first().begin(), t.first().end()), b);
}

}  // namespace
}  // namespace tlvlink::pipeline
