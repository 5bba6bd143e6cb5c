// Corruption injection on a pty pair: the board's Sender streams through a cable that replaces
// and drops bytes (seeded; TLVLINK_TEST_SEED replays); the host checks every field of every
// frame it accepts. No corrupted frame may be accepted, damaged ones are counted, and the link
// keeps delivering (the next good frame is decoded). tlvlink_corruption_table prints the full
// table of rates.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "pty_cable.h"
#include "stream_fixture.h"
#include "support/random.h"
#include "support/temp_dir.h"
#include "tlvlink/protocol/views.h"
#include "tlvlink/transport/sender.h"
#include "tlvlink/transport/serial.h"
#include "tlvlink/transport/time.h"
#include "transport/test_host.h"

namespace tlvlink::transport {
namespace {

using protocol::MessageType;

struct Rates {
  double error, drop;
};

class CorruptionTest : public ::testing::TestWithParam<Rates> {};

TEST_P(CorruptionTest, NoCorruptedFrameIsAccepted) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  const Rates rates = GetParam();
  testing::TempDir dir("corrupt");
  testing::PtyCable cable(dir.path(), testing::PtyCable::Faults{rates.error, rates.drop, seed});
  ASSERT_TRUE(cable.plug().ok());
  auto sender =
      Sender::create(make_serial_transport({cable.board_path(), 0, FlowControl::kNone}).value(), {})
          .value();
  ASSERT_TRUE(sender->set_hello(testing::fixture_hello()).ok());
  ASSERT_TRUE(sender->start().ok());
  testing::TestHost host(cable.host_path());
  for (int i = 0; i < 300 && !host.open().ok(); ++i) ::usleep(10'000);
  ASSERT_TRUE(host.is_open());
  host.pump(200);
  constexpr uint32_t kFrames = 2000;
  testing::PredictionStorage st;
  for (uint32_t n = 0; n < kFrames; ++n) {
    ASSERT_TRUE(sender->post(testing::fixture_prediction(n, st, n % 4 == 0)).ok());
    if (n % 50 == 49) host.pump(20);
  }
  host.pump(1500, [&] { return host.count(MessageType::kFramePrediction) >= kFrames; });
  std::set<uint32_t> intact;
  size_t corrupted = 0;
  for (const auto& m : host.messages) {
    if (m.header.type != MessageType::kFramePrediction) continue;
    testing::AlignedPayload p(m.payload);
    auto v = protocol::decode_frame_prediction(p.bytes());
    if (!v.ok() || !testing::fixture_prediction_intact(v.value()))
      ++corrupted;
    else
      intact.insert(v.value().frame_sequence());
  }
  const auto cc = cable.counts();
  EXPECT_EQ(corrupted, 0u) << "a damaged frame passed every check";
  EXPECT_GT(cc.corrupted + cc.dropped, 0u) << "the cable damaged nothing: the test tests nothing";
  EXPECT_GT(host.counters().rejected(), 0u);
  // Damage costs frames, but the stream goes on. A frame of L wire bytes survives with
  // probability (1 - p)^L; at least half of that expectation must arrive (the slack covers the
  // spread of a 2000-frame sample and delimiters lost with their frames).
  const SenderCounters sc = sender->counters();
  const double mean_bytes = static_cast<double>(sc.bytes_sent) /
                            static_cast<double>(std::max<uint64_t>(1, sc.frames_sent));
  const double expected = kFrames * std::pow(1 - rates.error - rates.drop, mean_bytes);
  EXPECT_GT(static_cast<double>(intact.size()), 0.5 * expected)
      << intact.size() << " of " << kFrames << ", expected about " << expected;
  // The stream goes on to the end: one of the last 100 frames arrives (even at 1 % damage,
  // where about 1 in 10 survives, missing all 100 has probability 0.9^100 = 3e-5).
  bool tail = false;
  for (uint32_t n = kFrames - 100; n < kFrames; ++n) tail = tail || intact.count(n) > 0;
  EXPECT_TRUE(tail);
  EXPECT_EQ(sender->counters().dropped_queue_full, 0u);
}

INSTANTIATE_TEST_SUITE_P(Rates, CorruptionTest,
                         ::testing::Values(Rates{1e-3, 0}, Rates{0, 1e-3}, Rates{1e-3, 1e-3},
                                           Rates{5e-3, 5e-3}),
                         [](const ::testing::TestParamInfo<Rates>& p) {
                           return "errors_" +
                                  std::to_string(static_cast<int>(p.param.error * 1e4)) +
                                  "e4_drops_" +
                                  std::to_string(static_cast<int>(p.param.drop * 1e4)) + "e4";
                         });

}  // namespace
}  // namespace tlvlink::transport
