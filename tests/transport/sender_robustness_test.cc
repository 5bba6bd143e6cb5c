// The board never blocks on the link, and both sides recover without a manual step:
// absent host (bounded queue, oldest dropped and counted, the rest delivered late and flagged),
// slow host (queue_full drops, nothing lost silently), host reader killed and restarted, the
// link itself gone and back (a "cable" of two ptys unplugged and replugged), stop() flushing,
// stale messages, and no heap allocation per posted message.
#include <gtest/gtest.h>

#include <set>

#include "pty_cable.h"
#include "stream_fixture.h"
#include "support/alloc_counter.h"
#include "support/temp_dir.h"
#include "tlvlink/protocol/views.h"
#include "tlvlink/transport/pty.h"
#include "tlvlink/transport/sender.h"
#include "tlvlink/transport/serial.h"
#include "tlvlink/transport/time.h"
#include "transport/test_host.h"

namespace tlvlink::transport {
namespace {

using protocol::MessageType;
using testing::AlignedPayload;
using testing::TestHost;

// A post() that waited for the link would take as long as the link is down (seconds here);
// this bound only says "did not wait", with room for a loaded CI machine.
constexpr int64_t kPostDidNotWaitNs = 200'000'000;

std::unique_ptr<Sender> make_sender(std::unique_ptr<Transport> t, SenderConfig config = {}) {
  auto s = Sender::create(std::move(t), config);
  EXPECT_TRUE(s.ok());
  EXPECT_TRUE(s.value()->set_hello(testing::fixture_hello()).ok());
  EXPECT_TRUE(s.value()->start().ok());
  return std::move(s.value());
}

// frame_sequence of every FramePrediction the host got, and whether each was flagged delayed.
std::vector<std::pair<uint32_t, bool>> predictions(const TestHost& host, size_t from = 0) {
  std::vector<std::pair<uint32_t, bool>> out;
  for (size_t i = from; i < host.messages.size(); ++i) {
    const auto& m = host.messages[i];
    if (m.header.type != MessageType::kFramePrediction) continue;
    AlignedPayload p(m.payload);
    auto v = protocol::decode_frame_prediction(p.bytes());
    EXPECT_TRUE(v.ok());
    EXPECT_TRUE(testing::fixture_prediction_intact(v.value()));
    out.emplace_back(v.value().frame_sequence(), (m.header.flags & protocol::kFlagDelayed) != 0);
  }
  return out;
}

void open_when_there(TestHost& host) {
  for (int i = 0; i < 300 && !host.open().ok(); ++i) ::usleep(10'000);
  ASSERT_TRUE(host.is_open());
}

TEST(SenderRobustness, AbsentHostNeverBlocksAndTheNewestArriveLate) {
  testing::TempDir dir("absent");
  SenderConfig config;
  config.queue_bytes = 64 * 1024;
  auto sender = make_sender(std::make_unique<PtyTransport>(PtyConfig{dir / "tty"}), config);
  testing::PredictionStorage st;
  int64_t slowest = 0;
  constexpr uint32_t kPosted = 5000;
  for (uint32_t i = 0; i < kPosted; ++i) {
    const int64_t t0 = monotonic_ns();
    ASSERT_TRUE(sender->post(testing::fixture_prediction(i, st)).ok());
    slowest = std::max(slowest, monotonic_ns() - t0);
  }
  EXPECT_LT(slowest, kPostDidNotWaitNs);
  const SenderCounters before = sender->counters();
  EXPECT_FALSE(before.link_up);
  EXPECT_EQ(before.link_error.code(), ErrorCode::kTransportUnavailable)
      << before.link_error.message();
  EXPECT_GT(before.dropped_link_down, 0u);
  EXPECT_EQ(before.dropped_queue_full, 0u);
  EXPECT_EQ(before.dropped_link_down + before.queue_messages, kPosted);
  EXPECT_LE(before.queue_bytes, config.queue_bytes);
  ASSERT_TRUE(sender->post(protocol::Stats{}).ok());

  TestHost host(dir / "tty");
  open_when_there(host);
  ASSERT_TRUE(host.wait_for(
      5000, [&] { return host.count(MessageType::kFramePrediction) == before.queue_messages; }));
  ASSERT_GE(host.messages.size(), 2u);
  EXPECT_EQ(host.messages[0].header.type, MessageType::kHello);
  EXPECT_EQ(host.messages[1].header.type, MessageType::kStats)
      << "the newest Stats goes before the backlog";
  EXPECT_NE(host.messages[1].header.flags & protocol::kFlagDelayed, 0)
      << "made while the link was down: DELAYED though sent after the reconnect (issue 31)";
  const AlignedPayload stats_bytes(host.messages[1].payload);
  auto stats = protocol::decode_stats(stats_bytes.bytes());
  ASSERT_TRUE(stats.ok());
  EXPECT_EQ(stats.value().drop(1).cause, protocol::DropCause::kLinkDown);
  EXPECT_EQ(stats.value().drop(1).count, before.dropped_link_down)
      << "the drops are in the next Stats";
  const auto got = predictions(host);
  // The newest ones, oldest dropped first, in order, all flagged as sent late.
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].first, kPosted - got.size() + i);
    EXPECT_TRUE(got[i].second);
  }
  EXPECT_TRUE(sender->counters().link_up);
}

TEST(SenderRobustness, SlowHostLosesNothingSilently) {
  testing::TempDir dir("slow");
  SenderConfig config;
  config.queue_bytes = 32 * 1024;
  config.flush_ms = 5000;
  auto sender = make_sender(std::make_unique<PtyTransport>(PtyConfig{dir / "tty"}), config);
  TestHost host(dir / "tty");
  open_when_there(host);
  testing::PredictionStorage st;
  constexpr uint32_t kPosted = 4000;
  for (uint32_t i = 0; i < kPosted; ++i) {
    ASSERT_TRUE(sender->post(testing::fixture_prediction(i, st, /*with_embedding=*/true)).ok());
    if (i % 200 == 0) host.pump(5);  // a host that reads in short bursts
  }
  std::thread stopper([&] { sender->stop(); });  // stop() flushes what is left
  host.pump(3000, [&] {
    return host.count(MessageType::kFramePrediction) + sender->counters().dropped_queue_full >=
           kPosted;
  });
  stopper.join();
  const SenderCounters c = sender->counters();
  const auto got = predictions(host);
  EXPECT_GT(c.dropped_queue_full, 0u) << "the host was slower than the board";
  EXPECT_EQ(got.size() + c.dropped_queue_full + c.dropped_link_down, kPosted)
      << got.size() << " received, " << c.dropped_queue_full << " + " << c.dropped_link_down
      << " dropped, " << c.frames_sent << " frames sent, host "
      << (host.disconnected ? "saw hangup" : "open") << ", rejected " << host.counters().rejected();
  for (size_t i = 1; i < got.size(); ++i) ASSERT_LT(got[i - 1].first, got[i].first) << "order kept";
}

TEST(SenderRobustness, HostReaderKilledAndRestarted) {
  testing::TempDir dir("restart");
  auto sender = make_sender(std::make_unique<PtyTransport>(PtyConfig{dir / "tty"}));
  testing::PredictionStorage st;
  TestHost first(dir / "tty");
  open_when_there(first);
  for (uint32_t i = 0; i < 100; ++i)
    ASSERT_TRUE(sender->post(testing::fixture_prediction(i, st)).ok());
  // Reads part of the stream (the board has seen it connect: the Hello came), then dies.
  ASSERT_TRUE(
      first.wait_for(5000, [&] { return first.count(MessageType::kFramePrediction) >= 20; }));
  first.close();
  for (uint32_t i = 100; i < 300; ++i)
    ASSERT_TRUE(sender->post(testing::fixture_prediction(i, st)).ok());
  ::usleep(300'000);  // longer than the board's idle wait (100 ms): it notices the reader left
  TestHost second(dir / "tty");
  open_when_there(second);
  ASSERT_TRUE(second.wait_for(5000, [&] {
    const auto p = predictions(second);
    return !p.empty() && p.back().first == 299;
  }));
  std::set<uint32_t> seen;
  for (const auto& [n, delayed] : predictions(first)) seen.insert(n);
  for (const auto& [n, delayed] : predictions(second)) seen.insert(n);
  // At most the frame the first reader had half read when it died is gone: it had left the board.
  EXPECT_GE(seen.size(), 299u);
  EXPECT_EQ(second.count(MessageType::kHello), 1u) << "the new reader is greeted";
  EXPECT_GE(sender->counters().reconnects, 1u);
  EXPECT_EQ(sender->counters().dropped_link_down, 0u) << "the queue held the outage";
}

TEST(SenderRobustness, LinkGoneAndBack) {
  testing::TempDir dir("cable");
  testing::PtyCable cable(dir.path());
  ASSERT_TRUE(cable.plug().ok());
  SenderConfig config;
  config.reconnect_max_ms = 200;
  auto sender = make_sender(
      make_serial_transport({cable.board_path(), 0, FlowControl::kNone}).value(), config);
  TestHost host(cable.host_path());
  open_when_there(host);
  testing::PredictionStorage st;
  for (uint32_t i = 0; i < 100; ++i)
    ASSERT_TRUE(sender->post(testing::fixture_prediction(i, st)).ok());
  ASSERT_TRUE(
      host.wait_for(5000, [&] { return host.count(MessageType::kFramePrediction) == 100; }));

  cable.unplug();  // both ends vanish, as when the USB cable is pulled
  host.pump(200);
  EXPECT_TRUE(host.disconnected) << "the host saw the hangup";
  ::usleep(300'000);
  EXPECT_FALSE(sender->counters().link_up);
  for (uint32_t i = 100; i < 200; ++i)
    ASSERT_TRUE(sender->post(testing::fixture_prediction(i, st)).ok());

  ASSERT_TRUE(cable.plug().ok());  // back at the same paths
  open_when_there(host);
  const size_t mark = host.messages.size();
  ASSERT_TRUE(host.wait_for(5000, [&] { return predictions(host, mark).size() == 100; }));
  const auto after = predictions(host, mark);
  for (size_t i = 0; i < after.size(); ++i) {
    EXPECT_EQ(after[i].first, 100 + i);
    EXPECT_TRUE(after[i].second) << "made while the link was down";
  }
  EXPECT_EQ(host.messages[mark].header.type, MessageType::kHello);
  EXPECT_TRUE(sender->counters().link_up);
  EXPECT_GE(sender->counters().reconnects, 1u);
}

TEST(SenderRobustness, StopFlushesWhatIsQueued) {
  testing::TempDir dir("flush");
  auto sender = make_sender(std::make_unique<PtyTransport>(PtyConfig{dir / "tty"}));
  TestHost host(dir / "tty");
  open_when_there(host);
  ASSERT_TRUE(host.wait_for(2000, [&] { return host.count(MessageType::kHello) == 1; }));
  testing::PredictionStorage st;
  for (uint32_t i = 0; i < 50; ++i)
    ASSERT_TRUE(sender->post(testing::fixture_prediction(i, st)).ok());
  std::thread stopper([&] { sender->stop(); });
  host.pump(2000, [&] { return host.count(MessageType::kFramePrediction) == 50; });
  stopper.join();
  EXPECT_EQ(host.count(MessageType::kFramePrediction), 50u);
}

TEST(SenderRobustness, StaleMessagesAreDroppedAndCounted) {
  testing::TempDir dir("stale");
  SenderConfig config;
  config.max_age_ms = 300;
  auto sender = make_sender(std::make_unique<PtyTransport>(PtyConfig{dir / "tty"}), config);
  testing::PredictionStorage st;
  for (uint32_t i = 0; i < 10; ++i)
    ASSERT_TRUE(sender->post(testing::fixture_prediction(i, st)).ok());
  ::usleep(600'000);
  for (uint32_t i = 10; i < 20; ++i)
    ASSERT_TRUE(sender->post(testing::fixture_prediction(i, st)).ok());
  TestHost host(dir / "tty");
  open_when_there(host);
  ASSERT_TRUE(host.wait_for(3000, [&] { return host.count(MessageType::kFramePrediction) == 10; }));
  EXPECT_EQ(predictions(host).front().first, 10u);
  EXPECT_EQ(sender->counters().dropped_stale, 10u);
}

TEST(SenderRobustness, PostingAllocatesNothing) {
  testing::TempDir dir("alloc");
  auto sender = make_sender(std::make_unique<PtyTransport>(PtyConfig{dir / "tty"}));
  TestHost host(dir / "tty");
  open_when_there(host);
  ASSERT_TRUE(host.wait_for(2000, [&] { return host.count(MessageType::kHello) == 1; }));
  testing::PredictionStorage st;
  // Counts every thread's allocations: the posts and the link thread writing them out (into
  // the pty until the kernel buffer is full, then stalled).
  testing::start_counting_allocations();
  for (uint32_t i = 0; i < 1000; ++i) (void)sender->post(testing::fixture_prediction(i, st, true));
  protocol::Stats s;
  (void)sender->post(s);
  ::usleep(50'000);
  const size_t allocations = testing::stop_counting_allocations();
  EXPECT_EQ(allocations, 0u);
}

}  // namespace
}  // namespace tlvlink::transport
