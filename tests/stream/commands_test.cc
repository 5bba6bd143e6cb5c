// A controller's commands: text lines and the protocol's Command messages.
#include "tlvlink/stream/commands.h"

#include <gtest/gtest.h>

namespace tlvlink::stream {
namespace {

TEST(Commands, TextLines) {
  Command c;
  ASSERT_TRUE(parse_command("closed\n", 5, c));
  EXPECT_EQ(c.kind, CommandKind::kClosed);
  EXPECT_EQ(c.t_ns, 5);
  ASSERT_TRUE(parse_command("rezero 2", 6, c));
  EXPECT_EQ(c.kind, CommandKind::kRezero);
  EXPECT_EQ(c.sensor, 2);
  ASSERT_TRUE(parse_command("rezero", 6, c));
  EXPECT_EQ(c.sensor, -1);
  EXPECT_FALSE(parse_command("rezero x", 6, c));
  EXPECT_FALSE(parse_command("rezeroes", 6, c));
  EXPECT_FALSE(parse_command("open", 6, c));
}

TEST(Commands, FromProtocol) {
  protocol::Command p;
  p.kind = protocol::CommandKind::kGraspClosed;
  p.event_ns = 123;
  auto c = from_protocol(p, 999);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c->kind, CommandKind::kClosed);
  EXPECT_EQ(c->t_ns, 123);
  p.kind = protocol::CommandKind::kRezero;
  p.event_ns = 0;  // none given: the board's time
  p.sensor = 1;
  auto r = from_protocol(p, 999);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->t_ns, 999);
  EXPECT_EQ(r->sensor, 1);
  p.sensor = protocol::kNoSensor;
  EXPECT_EQ(from_protocol(p, 999)->sensor, -1);
  p.kind = protocol::CommandKind::kStart;
  auto refused = from_protocol(p, 999);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code(), ErrorCode::kProtocolUnsupported);
}

}  // namespace
}  // namespace tlvlink::stream
