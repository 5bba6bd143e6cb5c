// The C++ client against a real Sender over a pty: Hello and predictions, the clock offset, its
// own commands' replies consumed and the user's delivered, a board that is not there yet, a board
// that restarts (reconnect, new boot id), and a board of another major version.
#include <gtest/gtest.h>

#include <cstdlib>

#include "stream_fixture.h"
#include "support/temp_dir.h"
#include "tlvlink/listen/client.h"
#include "tlvlink/listen/command_text.h"
#include "tlvlink/protocol/encode.h"
#include "tlvlink/transport/pty.h"
#include "tlvlink/transport/sender.h"
#include "tlvlink/transport/time.h"

namespace tlvlink::listen {
namespace {

using protocol::MessageType;

std::unique_ptr<transport::Sender> start_board(const std::string& link, uint64_t boot_id = 0x5EED) {
  auto s = transport::Sender::create(
      std::make_unique<transport::PtyTransport>(transport::PtyConfig{link}), {});
  EXPECT_TRUE(s.ok());
  protocol::Hello hello = testing::fixture_hello();
  hello.boot_id = boot_id;
  EXPECT_TRUE(s.value()->set_hello(hello).ok());
  EXPECT_TRUE(s.value()
                  ->set_command_handler([](const protocol::Command& c) -> Status {
                    if (c.kind == protocol::CommandKind::kSetConfig)
                      return Error(ErrorCode::kInvalidArgument, "no such key");
                    return Status();
                  })
                  .ok());
  EXPECT_TRUE(s.value()->start().ok());
  return std::move(s.value());
}

// Pulls messages until `done` or `ms` pass; returns them.
std::vector<Message> pull(Client& c, int ms,
                          const std::function<bool(const std::vector<Message>&)>& done) {
  std::vector<Message> got;
  const int64_t end = transport::monotonic_ns() + int64_t{ms} * 1'000'000;
  while (transport::monotonic_ns() < end && !done(got)) {
    Result<std::optional<Message>> m = c.next(50);
    EXPECT_TRUE(m.ok());
    if (m.ok() && m.value()) got.push_back(std::move(*m.value()));
  }
  return got;
}

size_t count(const std::vector<Message>& v, MessageType t) {
  size_t n = 0;
  for (const Message& m : v) n += m.type() == t;
  return n;
}

TEST(Client, ReceivesHelloPredictionsAndPutsThemOnItsClock) {
  testing::TempDir dir("client");
  auto board = start_board(dir / "tty");
  auto c = Client::open("serial:" + dir / "tty");
  ASSERT_TRUE(c.ok()) << c.error().message();
  Client& client = *c.value();
  // Wait until the board is greeted and the clock has a few exchanges.
  auto got = pull(client, 3000, [&](const auto& v) {
    return count(v, MessageType::kHello) >= 1 && client.clock().samples >= 3;
  });
  ASSERT_GE(count(got, MessageType::kHello), 1u);
  testing::PredictionStorage st;
  for (uint32_t i = 0; i < 50; ++i) {
    ASSERT_TRUE(
        board->post(testing::fixture_prediction(i, st, false, transport::monotonic_ns())).ok());
  }
  got = pull(client, 3000,
             [](const auto& v) { return count(v, MessageType::kFramePrediction) == 50; });
  ASSERT_EQ(count(got, MessageType::kFramePrediction), 50u);
  EXPECT_EQ(count(got, MessageType::kPong) + count(got, MessageType::kAck), 0u)
      << "replies to the client's own Info and TimeSync are consumed";
  // Same machine, same clock: the true offset is 0, within the estimate's bound.
  const protocol::ClockEstimate e = client.clock();
  ASSERT_TRUE(e.valid);
  EXPECT_LE(std::llabs(e.offset_ns), e.uncertainty_ns) << "offset " << e.offset_ns;
  for (const Message& m : got) {
    auto f = m.frame_prediction();
    ASSERT_TRUE(f.ok());
    EXPECT_TRUE(testing::fixture_prediction_intact(f.value()));
    EXPECT_TRUE(m.clock().valid);
    // Capture (board clock) -> receive (host clock): positive and small on a local pty.
    EXPECT_GE(m.receive_ns(), m.to_host_ns(f.value().timing().capture_ns) - e.uncertainty_ns);
  }
  const LinkStats s = client.stats();
  EXPECT_EQ(s.frames.rejected(), 0u);
  EXPECT_EQ(s.sequence_gaps, 0u);
  EXPECT_GE(s.capture_latency.count(), 50u);
}

TEST(Client, UserCommandsGetTheirRepliesDelivered) {
  testing::TempDir dir("client");
  auto board = start_board(dir / "tty");
  auto c = Client::open("serial:" + dir / "tty");
  Client& client = *c.value();
  (void)pull(client, 3000, [](const auto& v) { return count(v, MessageType::kHello) >= 1; });
  Result<uint32_t> ping = client.send(parse_command("ping").value());
  Result<uint32_t> start = client.send(parse_command("start 1").value());
  Result<uint32_t> set = client.send(parse_command("set treads=2").value());
  ASSERT_TRUE(ping.ok() && start.ok() && set.ok());
  auto got = pull(client, 3000, [](const auto& v) {
    return count(v, MessageType::kPong) == 1 && count(v, MessageType::kAck) == 1 &&
           count(v, MessageType::kNack) == 1;
  });
  for (const Message& m : got) {
    if (auto p = m.pong(); p.ok()) {
      EXPECT_EQ(p.value().command_sequence, ping.value());
    }
    if (auto a = m.ack(); a.ok()) {
      EXPECT_EQ(a.value().command_sequence, start.value());
    }
    if (auto n = m.nack(); n.ok()) {
      EXPECT_EQ(n.value().command_sequence, set.value());
      EXPECT_EQ(n.value().text, "no such key");
    }
  }
  EXPECT_EQ(count(got, MessageType::kNack), 1u);
}

TEST(Client, WaitsForABoardThatIsNotThereYetThenReconnectsAfterARestart) {
  testing::TempDir dir("client");
  auto c = Client::open("serial:" + dir / "tty");
  ASSERT_TRUE(c.ok()) << "an absent device is not an error for a reconnecting client";
  Client& client = *c.value();
  EXPECT_FALSE(client.next(300).value().has_value());
  Result<uint32_t> early = client.send(parse_command("ping").value());
  ASSERT_FALSE(early.ok());
  EXPECT_EQ(early.error().code(), ErrorCode::kTransportUnavailable);
  auto events = client.take_events();
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events[0].kind, LinkEvent::Kind::kDisconnected);

  auto board = start_board(dir / "tty", 1);
  auto got = pull(client, 5000, [](const auto& v) { return count(v, MessageType::kHello) >= 1; });
  ASSERT_GE(count(got, MessageType::kHello), 1u);

  board->stop();  // the board goes away (daemon restart)...
  board.reset();
  (void)pull(client, 500, [](const auto&) { return false; });
  board = start_board(dir / "tty", 2);  // ...and comes back with a new boot id
  testing::PredictionStorage st;
  ASSERT_TRUE(board->post(testing::fixture_prediction(7, st)).ok());
  got = pull(client, 5000,
             [](const auto& v) { return count(v, MessageType::kFramePrediction) >= 1; });
  ASSERT_EQ(count(got, MessageType::kFramePrediction), 1u);
  const LinkStats s = client.stats();
  EXPECT_EQ(s.board_restarts, 1u);
  EXPECT_GE(s.connects, 2u);
  EXPECT_GE(s.disconnects, 1u);
  EXPECT_EQ(client.hello()->hello().value().boot_id(), 2u);
  bool restart_event = false;
  for (const LinkEvent& e : client.take_events())
    restart_event |= e.kind == LinkEvent::Kind::kBoardRestarted;
  EXPECT_TRUE(restart_event);
}

TEST(Client, RefusesAnotherMajorVersionWithAClearMessage) {
  testing::TempDir dir("client");
  transport::PtyTransport board({dir / "tty"});
  ASSERT_TRUE(board.open().ok());
  ClientOptions options;
  options.time_sync_ms = 0;
  auto c = Client::open("serial:" + dir / "tty", options);
  Client& client = *c.value();
  (void)client.next(200);
  alignas(8) static std::byte scratch[protocol::kEncodeBufferSize];
  std::byte wire[protocol::kMaxWireFrameSize];
  protocol::FrameHeader h;
  h.version_major = 2;
  Result<size_t> n = protocol::encode_message(testing::fixture_hello(), h, scratch, wire);
  for (int i = 0; i < 3 && n.ok(); ++i) {
    (void)board.wait(true, 100);
    ASSERT_TRUE(board.write(std::span<const std::byte>(wire, n.value())).ok());
  }
  (void)pull(client, 500, [](const auto&) { return false; });
  int mismatches = 0;
  for (const LinkEvent& e : client.take_events()) {
    if (e.kind != LinkEvent::Kind::kVersionMismatch) continue;
    ++mismatches;
    const std::string minor = std::to_string(protocol::kVersionMinor);
    EXPECT_NE(
        e.text.find("board speaks stream protocol 2." + minor + "; this client speaks 1." + minor),
        std::string::npos)
        << e.text;
  }
  EXPECT_EQ(mismatches, 1) << "said once per connection";
  EXPECT_EQ(client.stats().frames.version, 3u);
  EXPECT_FALSE(client.hello().has_value());
}

TEST(Client, SourceStringsAreChecked) {
  EXPECT_EQ(Client::open("tcp:1.2.3.4").error().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(Client::open("serial:/dev/x,baud=7").error().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(Client::open("usb:12345:1").error().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(Client::open("replay:/nonexistent/file").error().code(), ErrorCode::kIo);
}

}  // namespace
}  // namespace tlvlink::listen
