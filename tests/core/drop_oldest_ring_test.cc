// The drop-oldest ring: overflow drops the oldest and counts it, wrap-around, full / empty,
// try_push refusing the newest, and one producer and one consumer thread around a mutex (as its
// owners use it).
#include "tlvlink/drop_oldest_ring.h"

#include <array>
#include <mutex>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace tlvlink {
namespace {

std::vector<int> drain(DropOldestRing<int>& ring) {
  std::vector<int> out;
  int v = 0;
  while (ring.pop(v)) out.push_back(v);
  return out;
}

TEST(DropOldestRing, EmptyAndFull) {
  std::array<int, 3> storage{};
  DropOldestRing<int> ring(storage);
  EXPECT_TRUE(ring.empty());
  EXPECT_FALSE(ring.full());
  EXPECT_EQ(ring.capacity(), 3u);
  int v = 0;
  EXPECT_FALSE(ring.pop(v));
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(ring.push(i));
  EXPECT_TRUE(ring.full());
  EXPECT_EQ(ring.size(), 3u);
  EXPECT_EQ(ring.front(), 0);
  EXPECT_EQ(ring.dropped(), 0u);
  ring.clear();
  EXPECT_TRUE(ring.empty());
}

TEST(DropOldestRing, OverflowDropsTheOldestAndCountsIt) {
  std::array<int, 3> storage{};
  DropOldestRing<int> ring(storage);
  for (int i = 0; i < 3; ++i) ring.push(i);
  EXPECT_TRUE(ring.push(3));
  EXPECT_TRUE(ring.push(4));
  EXPECT_EQ(ring.dropped(), 2u);
  EXPECT_EQ(drain(ring), (std::vector<int>{2, 3, 4}));
}

TEST(DropOldestRing, WrapsAroundManyTimesInOrder) {
  std::array<int, 4> storage{};
  DropOldestRing<int> ring(storage);
  int next_in = 0, next_out = 0;
  // Uneven push / pop batches walk head and tail around the storage many times.
  for (int round = 0; round < 50; ++round) {
    for (int k = 0; k < 1 + round % 3; ++k) ring.push(next_in++);
    int v = 0;
    for (int k = 0; k < 1 + (round + 1) % 3 && ring.pop(v); ++k) {
      EXPECT_EQ(v, next_out) << "round " << round;
      next_out = v + 1;
    }
  }
  EXPECT_EQ(ring.dropped(), 0u);
  EXPECT_EQ(static_cast<size_t>(next_in - next_out), ring.size());
}

TEST(DropOldestRing, TryPushRefusesTheNewest) {
  std::array<int, 2> storage{};
  DropOldestRing<int> ring(storage);
  EXPECT_TRUE(ring.try_push(1));
  EXPECT_TRUE(ring.try_push(2));
  EXPECT_FALSE(ring.try_push(3));
  EXPECT_EQ(ring.rejected(), 1u);
  EXPECT_EQ(ring.dropped(), 0u);
  EXPECT_EQ(drain(ring), (std::vector<int>{1, 2}));
}

TEST(DropOldestRing, ZeroCapacityLosesEverythingCounted) {
  DropOldestRing<int> ring(std::span<int>{});
  EXPECT_TRUE(ring.push(1));
  EXPECT_EQ(ring.dropped(), 1u);
  EXPECT_TRUE(ring.empty());
}

TEST(DropOldestRing, OneProducerOneConsumerLoseNothingUncounted) {
  std::array<int, 8> storage{};
  DropOldestRing<int> ring(storage);
  std::mutex mutex;
  constexpr int kItems = 100000;
  std::vector<int> got;
  got.reserve(kItems);
  std::thread producer([&] {
    for (int i = 0; i < kItems; ++i) {
      std::lock_guard lock(mutex);
      ring.push(i);
    }
  });
  bool done = false;
  while (!done) {
    std::lock_guard lock(mutex);
    int v = 0;
    while (ring.pop(v)) got.push_back(v);
    done = !got.empty() && got.back() == kItems - 1;
  }
  producer.join();
  for (size_t i = 1; i < got.size(); ++i) ASSERT_LT(got[i - 1], got[i]) << "out of order at " << i;
  EXPECT_EQ(got.size() + ring.dropped(), static_cast<size_t>(kItems));
}

}  // namespace
}  // namespace tlvlink
