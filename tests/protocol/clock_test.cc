// Clock offset estimation from Ping/Pong exchanges: the estimate and its bound against a
// simulated board clock with a known offset and random, asymmetric link delays (seeded).
#include <gtest/gtest.h>

#include <cstdlib>

#include "support/random.h"
#include "tlvlink/protocol/clock.h"

namespace tlvlink::protocol {
namespace {

TEST(ClockSync, SymmetricExchangeGivesTheExactOffset) {
  ClockSync c;
  // Board clock = host clock + 5 s; 100 us each way; the board takes 20 us to answer.
  const int64_t offset = 5'000'000'000;
  ASSERT_TRUE(c.add({1000, 1000 + 100'000 + offset, 1000 + 120'000 + offset, 1000 + 220'000}));
  const ClockEstimate e = c.estimate(1000 + 220'000);
  ASSERT_TRUE(e.valid);
  EXPECT_EQ(e.offset_ns, offset);
  EXPECT_EQ(e.delay_ns, 200'000);
  EXPECT_EQ(c.board_to_host(offset + 77), 77);
  EXPECT_EQ(c.host_to_board(77), offset + 77);
}

TEST(ClockSync, BoundHoldsUnderRandomAsymmetricDelays) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  ClockSync c;
  const int64_t offset = -123'456'789;
  int64_t host = 10'000'000'000;
  for (int i = 0; i < 200; ++i) {
    const int64_t up = rng.int_in(50'000, 3'000'000), down = rng.int_in(50'000, 3'000'000);
    const int64_t turn = rng.int_in(1'000, 200'000);
    const ClockSample s{host, host + up + offset, host + up + turn + offset,
                        host + up + turn + down};
    ASSERT_TRUE(c.add(s));
    const ClockEstimate e = c.estimate(s.t4);
    ASSERT_TRUE(e.valid);
    ASSERT_LE(std::llabs(e.offset_ns - offset), e.uncertainty_ns) << "exchange " << i;
    host += 1'000'000'000;
  }
}

TEST(ClockSync, PicksTheLeastDelayedExchange) {
  ClockSync c;
  // One quick exchange among slow, lopsided ones: its offset wins.
  ASSERT_TRUE(c.add({0, 9'000'000, 9'000'000, 10'000'000}));  // 9 ms up, 1 ms down
  ASSERT_TRUE(c.add({100, 150, 150, 200}));                   // 50 ns each way, offset 0
  ASSERT_TRUE(c.add({1000, 1000 + 8'000'000, 1000 + 8'000'000, 1000 + 9'000'000}));
  EXPECT_EQ(c.estimate(200).offset_ns, 0);
  EXPECT_EQ(c.estimate(200).delay_ns, 100);
  // After kWindow newer exchanges the quick one has aged out.
  for (size_t i = 0; i < ClockSync::kWindow; ++i) {
    const int64_t t = 1'000'000 * static_cast<int64_t>(i + 10);
    ASSERT_TRUE(c.add({t, t + 2000 + 500, t + 2000 + 500, t + 4000}));
  }
  EXPECT_EQ(c.estimate(0).delay_ns, 4000);
  EXPECT_EQ(c.estimate(0).samples, ClockSync::kWindow);
}

TEST(ClockSync, InconsistentExchangesAreIgnored) {
  ClockSync c;
  EXPECT_FALSE(c.add({100, 0, 0, 50}));    // received before sent
  EXPECT_FALSE(c.add({0, 100, 50, 200}));  // board answered before receiving
  EXPECT_FALSE(c.add({0, 0, 500, 100}));   // board turnaround longer than the round trip
  EXPECT_FALSE(c.estimate(0).valid);
  EXPECT_EQ(c.board_to_host(1234), 1234);
}

TEST(ClockSync, BoundGrowsWithAgeAndResetForgets) {
  ClockSync c;
  ASSERT_TRUE(c.add({0, 500, 500, 1000}));
  const int64_t fresh = c.estimate(1000).uncertainty_ns;
  const int64_t aged = c.estimate(1000 + 10'000'000'000).uncertainty_ns;  // 10 s later
  EXPECT_EQ(aged - fresh, 10'000 * ClockSync::kDriftPartsPerMillion);
  c.reset();
  EXPECT_FALSE(c.estimate(0).valid);
}

}  // namespace
}  // namespace tlvlink::protocol
