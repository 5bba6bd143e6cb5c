// The Sender's protocol behaviour over a real pty: Hello first, predictions in order, every
// command answered (Pong, Hello + Ack, the handler's Ack or Nack), malformed and newer-version
// input refused clearly, Stats carrying the link counters.
#include <gtest/gtest.h>

#include <cmath>

#include "stream_fixture.h"
#include "support/temp_dir.h"
#include "tlvlink/protocol/encode.h"
#include "tlvlink/protocol/names.h"
#include "tlvlink/protocol/views.h"
#include "tlvlink/transport/pty.h"
#include "tlvlink/transport/sender.h"
#include "tlvlink/transport/time.h"
#include "transport/test_host.h"

namespace tlvlink::transport {
namespace {

using protocol::MessageType;
using testing::AlignedPayload;
using testing::TestHost;

struct Rig {
  testing::TempDir dir{"sender"};
  std::unique_ptr<Sender> sender;
  TestHost host{dir / "tty"};
  struct Handled {
    protocol::CommandKind kind;
    uint32_t grasp_id;
    int64_t event_ns;
    std::string key;  // copied: the command's strings are views into the frame
  };
  std::vector<Handled> handled;

  explicit Rig(bool with_handler = true, SenderConfig config = {}) {
    auto s = Sender::create(std::make_unique<PtyTransport>(PtyConfig{dir / "tty"}), config);
    EXPECT_TRUE(s.ok());
    sender = std::move(s.value());
    EXPECT_TRUE(sender->set_hello(testing::fixture_hello()).ok());
    if (with_handler) {
      EXPECT_TRUE(sender
                      ->set_command_handler([this](const protocol::Command& c) -> Status {
                        handled.push_back({c.kind, c.grasp_id, c.event_ns, std::string(c.key)});
                        if (c.kind == protocol::CommandKind::kSetConfig && c.key == "bad") {
                          return Error(ErrorCode::kInvalidArgument, "unknown key 'bad'");
                        }
                        return Status();
                      })
                      .ok());
    }
    EXPECT_TRUE(sender->start().ok());
  }
  // Opens the host side once the sender's pty exists.
  void connect() {
    for (int i = 0; i < 200 && !host.open().ok(); ++i) ::usleep(10'000);
    ASSERT_TRUE(host.is_open());
  }
};

TEST(Sender, HelloFirstThenPredictionsInOrder) {
  Rig rig;
  rig.connect();
  // Once the Hello is here the board knows the link is up: nothing after it is "delayed".
  ASSERT_TRUE(rig.host.wait_for(2000, [&] { return rig.host.count(MessageType::kHello) == 1; }));
  testing::PredictionStorage st;
  for (uint32_t i = 0; i < 100; ++i)
    ASSERT_TRUE(rig.sender->post(testing::fixture_prediction(i, st)).ok());
  ASSERT_TRUE(rig.host.wait_for(
      5000, [&] { return rig.host.count(MessageType::kFramePrediction) == 100; }));
  ASSERT_EQ(rig.host.messages.front().header.type, MessageType::kHello);
  const AlignedPayload hello_bytes(rig.host.messages.front().payload);
  Result<protocol::HelloView> hello = protocol::decode_hello(hello_bytes.bytes());
  ASSERT_TRUE(hello.ok());
  EXPECT_EQ(hello.value().device(), "test-board");
  EXPECT_EQ(hello.value().schema_hash(), protocol::schema_hash());
  uint32_t expect = 0, last_seq = rig.host.messages.front().header.sequence;
  for (size_t i = 1; i < rig.host.messages.size(); ++i) {
    const auto& m = rig.host.messages[i];
    EXPECT_EQ(m.header.sequence, last_seq + 1) << "no gap on a clean link";
    last_seq = m.header.sequence;
    ASSERT_EQ(m.header.type, MessageType::kFramePrediction);
    AlignedPayload p(m.payload);
    auto v = protocol::decode_frame_prediction(p.bytes());
    ASSERT_TRUE(v.ok());
    EXPECT_EQ(v.value().frame_sequence(), expect++);
    EXPECT_TRUE(testing::fixture_prediction_intact(v.value()));
    EXPECT_EQ(m.header.flags & protocol::kFlagDelayed, 0) << "sent while the link was up";
  }
  // The counters move once write() returned, which may be just after the host read the bytes.
  for (int i = 0; i < 100 && rig.sender->counters().frames_sent < 101; ++i) ::usleep(10'000);
  const SenderCounters c = rig.sender->counters();
  EXPECT_TRUE(c.link_up);
  EXPECT_EQ(c.frames_sent, 101u);
  EXPECT_EQ(c.dropped_queue_full + c.dropped_link_down, 0u);
}

TEST(Sender, PingAndTimeSyncGetAPongWithTheThreeTimestamps) {
  Rig rig;
  rig.connect();
  ASSERT_TRUE(rig.host.wait_for(2000, [&] { return rig.host.count(MessageType::kHello) == 1; }));
  protocol::Command ping;
  ping.kind = protocol::CommandKind::kPing;
  Result<uint32_t> seq = rig.host.send(ping);
  ASSERT_TRUE(seq.ok());
  ASSERT_TRUE(rig.host.wait_for(2000, [&] { return rig.host.count(MessageType::kPong) == 1; }));
  const auto* m = rig.host.last(MessageType::kPong);
  Result<protocol::Pong> pong = protocol::decode_pong(AlignedPayload(m->payload).bytes());
  ASSERT_TRUE(pong.ok());
  EXPECT_EQ(pong.value().command_sequence, seq.value());
  // Same machine, same clock: t1 <= t2 <= t3 <= t4.
  EXPECT_LE(pong.value().host_send_ns, pong.value().board_receive_ns);
  EXPECT_LE(pong.value().board_receive_ns, m->header.send_ns);
  EXPECT_LE(m->header.send_ns, m->received_ns);

  protocol::Command sync;
  sync.kind = protocol::CommandKind::kTimeSync;
  sync.clock_offset_ns = 12345;
  sync.clock_uncertainty_ns = 678;
  ASSERT_TRUE(rig.host.send(sync).ok());
  ASSERT_TRUE(rig.host.wait_for(2000, [&] { return rig.host.count(MessageType::kPong) == 2; }));
  const protocol::ClockEstimate e = rig.sender->host_clock();
  EXPECT_TRUE(e.valid);
  EXPECT_EQ(e.offset_ns, 12345);
  EXPECT_EQ(e.uncertainty_ns, 678);
  EXPECT_EQ(rig.host.count(MessageType::kAck), 0u) << "a Pong is the whole answer";
}

TEST(Sender, InfoGetsTheHelloAndAnAck) {
  Rig rig;
  rig.connect();
  ASSERT_TRUE(rig.host.wait_for(2000, [&] { return rig.host.count(MessageType::kHello) == 1; }));
  protocol::Command info;
  info.kind = protocol::CommandKind::kInfo;
  Result<uint32_t> seq = rig.host.send(info);
  ASSERT_TRUE(rig.host.wait_for(2000, [&] { return rig.host.count(MessageType::kAck) == 1; }));
  EXPECT_EQ(rig.host.count(MessageType::kHello), 2u);
  Result<protocol::Ack> ack =
      protocol::decode_ack(AlignedPayload(rig.host.last(MessageType::kAck)->payload).bytes());
  EXPECT_EQ(ack.value().command_sequence, seq.value());
  EXPECT_EQ(ack.value().kind, protocol::CommandKind::kInfo);
}

TEST(Sender, PipelineCommandsReachTheHandlerAndAreAnswered) {
  Rig rig;
  rig.connect();
  protocol::Command start;
  start.kind = protocol::CommandKind::kStart;
  protocol::Command closed;
  closed.kind = protocol::CommandKind::kGraspClosed;
  closed.grasp_id = 17;
  closed.event_ns = 999;
  protocol::Command good, bad;
  good.kind = bad.kind = protocol::CommandKind::kSetConfig;
  good.key = "threads";
  good.value = "2";
  bad.key = "bad";
  for (const auto& c : {start, closed, good}) ASSERT_TRUE(rig.host.send(c).ok());
  Result<uint32_t> bad_seq = rig.host.send(bad);
  ASSERT_TRUE(rig.host.wait_for(2000, [&] {
    return rig.host.count(MessageType::kAck) == 3 && rig.host.count(MessageType::kNack) == 1;
  }));
  ASSERT_EQ(rig.handled.size(), 4u);
  EXPECT_EQ(rig.handled[1].grasp_id, 17u);
  EXPECT_EQ(rig.handled[1].event_ns, 999);
  EXPECT_EQ(rig.handled[2].key, "threads");
  const AlignedPayload nack_bytes(rig.host.last(MessageType::kNack)->payload);
  Result<protocol::Nack> nack = protocol::decode_nack(nack_bytes.bytes());
  EXPECT_EQ(nack.value().command_sequence, bad_seq.value());
  EXPECT_EQ(nack.value().code, static_cast<uint16_t>(ErrorCode::kInvalidArgument));
  EXPECT_EQ(nack.value().text, "unknown key 'bad'");
  EXPECT_EQ(rig.sender->counters().commands_refused, 1u);
}

TEST(Sender, WithoutAHandlerPipelineCommandsAreRefused) {
  Rig rig(/*with_handler=*/false);
  rig.connect();
  protocol::Command rezero;
  rezero.kind = protocol::CommandKind::kRezero;
  ASSERT_TRUE(rig.host.send(rezero).ok());
  ASSERT_TRUE(rig.host.wait_for(2000, [&] { return rig.host.count(MessageType::kNack) == 1; }));
  const AlignedPayload nack_bytes(rig.host.last(MessageType::kNack)->payload);
  auto nack = protocol::decode_nack(nack_bytes.bytes());
  EXPECT_EQ(nack.value().code, static_cast<uint16_t>(ErrorCode::kProtocolUnsupported));
  EXPECT_NE(std::string(nack.value().text).find("rezero"), std::string::npos) << nack.value().text;
}

TEST(Sender, MalformedUnknownAndNewerVersionInputIsRefusedClearly) {
  Rig rig;
  rig.connect();
  ASSERT_TRUE(rig.host.wait_for(2000, [&] { return rig.host.count(MessageType::kHello) == 1; }));
  alignas(8) static std::byte scratch[protocol::kEncodeBufferSize];
  std::byte wire[protocol::kMaxWireFrameSize];
  // A valid frame whose Command payload is garbage.
  protocol::FrameHeader h;
  h.type = MessageType::kCommand;
  h.sequence = 1000;
  const std::byte junk[8] = {std::byte{0xFF}, std::byte{0xFF}, std::byte{0xFF}, std::byte{0x7F}};
  Result<size_t> n = protocol::encode_frame(h, junk, wire);
  ASSERT_TRUE(rig.host.send_raw(std::span<const std::byte>(wire, n.value())).ok());
  // An unknown command kind.
  protocol::Command odd;
  odd.kind = static_cast<protocol::CommandKind>(77);
  ASSERT_TRUE(rig.host.send(odd).ok());
  // Two frames of a future major version (valid CRC): one clear ErrorReport.
  protocol::Command ping;
  ping.kind = protocol::CommandKind::kPing;
  h.version_major = 2;
  h.sequence = 1001;
  for (int i = 0; i < 2; ++i) {
    Result<size_t> future = protocol::encode_message(ping, h, scratch, wire);
    ASSERT_TRUE(rig.host.send_raw(std::span<const std::byte>(wire, future.value())).ok());
  }
  ASSERT_TRUE(rig.host.wait_for(2000, [&] {
    return rig.host.count(MessageType::kNack) == 2 && rig.host.count(MessageType::kError) == 1;
  }));
  rig.host.pump(100);
  EXPECT_EQ(rig.host.count(MessageType::kError), 1u) << "reported once per connection";
  EXPECT_EQ(rig.host.count(MessageType::kPong), 0u)
      << "frames of another major version are not obeyed";
  const AlignedPayload err_bytes(rig.host.last(MessageType::kError)->payload);
  auto err = protocol::decode_error_report(err_bytes.bytes());
  EXPECT_EQ(err.value().code, static_cast<uint16_t>(ErrorCode::kProtocolVersion));
  EXPECT_NE(std::string(err.value().text)
                .find("host speaks stream protocol 2." + std::to_string(protocol::kVersionMinor)),
            std::string::npos)
      << err.value().text;
  const auto* first_nack = &rig.host.messages[0];
  for (const auto& m : rig.host.messages) {
    if (m.header.type == MessageType::kNack) {
      first_nack = &m;
      break;
    }
  }
  const AlignedPayload first_nack_bytes(first_nack->payload);
  auto nack = protocol::decode_nack(first_nack_bytes.bytes());
  EXPECT_EQ(nack.value().command_sequence, 1000u);
  EXPECT_EQ(nack.value().code, static_cast<uint16_t>(ErrorCode::kProtocolMalformed));
  EXPECT_EQ(rig.sender->counters().frames_rejected, 2u);
}

TEST(Sender, StatsCarryTheLinkCountersAndItsDrops) {
  Rig rig;
  rig.connect();
  ASSERT_TRUE(rig.host.wait_for(2000, [&] { return rig.host.count(MessageType::kHello) == 1; }));
  // The board's own queue_full (its output queue) is merged with the link's: one entry a cause.
  const std::array<protocol::DropCount, 2> capture = {
      protocol::DropCount{protocol::DropCause::kCaptureGap, 5, 0},
      protocol::DropCount{protocol::DropCause::kQueueFull, 7, protocol::kNoSensor}};
  protocol::Stats s;
  s.uptime_ns = 1;
  s.drops = capture;
  ASSERT_TRUE(rig.sender->post(s).ok());
  ASSERT_TRUE(rig.host.wait_for(2000, [&] { return rig.host.count(MessageType::kStats) == 1; }));
  AlignedPayload p(rig.host.last(MessageType::kStats)->payload);
  auto v = protocol::decode_stats(p.bytes());
  ASSERT_TRUE(v.ok());
  ASSERT_EQ(v.value().drop_count(), 4u)
      << "each cause once (issue 31: queue_full and stale were listed twice)";
  EXPECT_EQ(v.value().drop(0).cause, protocol::DropCause::kCaptureGap);
  EXPECT_EQ(v.value().drop(1).cause, protocol::DropCause::kQueueFull);
  EXPECT_EQ(v.value().drop(1).count, 7u + rig.sender->counters().dropped_queue_full);
  EXPECT_EQ(v.value().drop(2).cause, protocol::DropCause::kLinkDown);
  EXPECT_EQ(v.value().drop(3).cause, protocol::DropCause::kStale);
  EXPECT_TRUE(v.value().link().link_up);
  EXPECT_EQ(v.value().link().queue_capacity_bytes, rig.sender->counters().queue_capacity_bytes);
}

TEST(Sender, LinkThreadPriorityIsAppliedOrReported) {
  SenderConfig config;
  config.realtime_priority = 5;
  Rig rig(true, config);
  // Root (or CAP_SYS_NICE / RLIMIT_RTPRIO) gets it; an unprivileged run is told it did not.
  const bool may = ::geteuid() == 0;
  if (may) {
    EXPECT_TRUE(rig.sender->counters().realtime);
  }
  rig.connect();
  EXPECT_TRUE(rig.host.wait_for(2000, [&] { return rig.host.count(MessageType::kHello) == 1; }))
      << "works either way";
}

TEST(Sender, ConfigurationIsChecked) {
  SenderConfig tiny;
  tiny.queue_bytes = 1000;
  Result<std::unique_ptr<Sender>> s =
      Sender::create(std::make_unique<PtyTransport>(PtyConfig{}), tiny);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kInvalidArgument);
  EXPECT_FALSE(Sender::create(nullptr, {}).ok());
  SenderConfig rt;
  rt.realtime_priority = 100;
  EXPECT_FALSE(Sender::create(std::make_unique<PtyTransport>(PtyConfig{}), rt).ok());
}

}  // namespace
}  // namespace tlvlink::transport
