// Commands as people type them, and choosing the board among USB devices (no device needed).
#include <gtest/gtest.h>

#include "tlvlink/listen/command_text.h"
#include "tlvlink/listen/usb_host.h"

namespace tlvlink::listen {
namespace {

using protocol::CommandKind;

TEST(CommandText, EveryCommand) {
  EXPECT_EQ(parse_command("start").value().kind, CommandKind::kStart);
  EXPECT_EQ(parse_command("start").value().sensor, protocol::kNoSensor);
  EXPECT_EQ(parse_command(" stop 1 ").value().sensor, 1);
  EXPECT_EQ(parse_command("closed 42").value().kind, CommandKind::kGraspClosed);
  EXPECT_EQ(parse_command("closed 42").value().grasp_id, 42u);
  EXPECT_EQ(parse_command("grasp_lifting 7").value().kind, CommandKind::kGraspLifting);
  EXPECT_EQ(parse_command("rezero 0").value().kind, CommandKind::kRezero);
  const protocol::Command set = parse_command("set heads = material,grasp").value();
  EXPECT_EQ(set.kind, CommandKind::kSetConfig);
  EXPECT_EQ(set.key, "heads");
  EXPECT_EQ(set.value, "material,grasp");
  EXPECT_EQ(parse_command("info").value().kind, CommandKind::kInfo);
  EXPECT_EQ(parse_command("ping").value().kind, CommandKind::kPing);
  EXPECT_EQ(parse_command("time_sync").value().kind, CommandKind::kTimeSync);
}

TEST(CommandText, MistakesAreNamed) {
  struct Bad {
    const char* text;
    const char* says;
  };
  for (const Bad& b : {Bad{"launch", "unknown command 'launch'"}, Bad{"closed", "needs a grasp id"},
                       Bad{"closed x", "grasp id 'x'"}, Bad{"start 255", "sensor '255'"},
                       Bad{"set threads", "KEY=VALUE"}, Bad{"ping now", "takes no argument"},
                       Bad{"", "unknown command"}}) {
    Result<protocol::Command> c = parse_command(b.text);
    ASSERT_FALSE(c.ok()) << b.text;
    EXPECT_EQ(c.error().code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(c.error().message()).find(b.says), std::string::npos)
        << c.error().message();
  }
}

TEST(UsbSelector, Parses) {
  EXPECT_EQ(parse_usb_selector("").value().vendor, transport::kUsbDefaultVendor);
  const UsbSelector s = parse_usb_selector("0c45:636d,serial=ABC").value();
  EXPECT_EQ(s.vendor, 0x0c45);
  EXPECT_EQ(s.product, 0x636d);
  EXPECT_EQ(s.serial, "ABC");
  EXPECT_EQ(parse_usb_selector(",serial=X").value().serial, "X");
  EXPECT_FALSE(parse_usb_selector("1d6b").ok());
  EXPECT_FALSE(parse_usb_selector("1d6b:xyz").ok());
  EXPECT_FALSE(parse_usb_selector("1d6b:0104,speed=high").ok());
}

UsbCandidate board(std::string serial, bool stream = true, bool accessible = true) {
  UsbCandidate c;
  c.vendor = 0x1d6b, c.product = 0x0104, c.serial = std::move(serial);
  c.has_stream_interface = stream, c.accessible = accessible;
  return c;
}

TEST(UsbSelect, ChoosesByIdsSerialAndInterface) {
  UsbSelector want;
  const std::vector<UsbCandidate> one = {board("A")};
  EXPECT_EQ(select_usb_device(one, want).value(), 0u);
  const std::vector<UsbCandidate> two = {board("A"), board("B")};
  Result<size_t> r = select_usb_device(two, want);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(std::string(r.error().message()).find("2 boards match"), std::string::npos)
      << r.error().message();
  want.serial = "B";
  EXPECT_EQ(select_usb_device(two, want).value(), 1u);
  want.serial = "C";
  Result<size_t> none = select_usb_device(two, want);
  EXPECT_EQ(none.error().code(), ErrorCode::kTransportUnavailable);
  EXPECT_NE(std::string(none.error().message()).find("serial 'A'"), std::string::npos)
      << "lists what it saw";
}

TEST(UsbSelect, SaysWhyADeviceIsNotUsable) {
  const std::vector<UsbCandidate> found = {board("A", /*stream=*/false),
                                           board("B", true, /*accessible=*/false)};
  Result<size_t> r = select_usb_device(found, UsbSelector{});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code(), ErrorCode::kTransportUnavailable);
  EXPECT_NE(std::string(r.error().message()).find("no tlvlink stream interface"), std::string::npos)
      << r.error().message();
  EXPECT_NE(std::string(r.error().message()).find("no permission"), std::string::npos)
      << r.error().message();
  EXPECT_NE(std::string(select_usb_device({}, UsbSelector{}).error().message()).find("no board"),
            std::string::npos);
}

TEST(UsbHost, AbsentBoardIsUnavailable) {
  Result<std::unique_ptr<transport::Transport>> t =
      make_usb_host_transport(UsbSelector{0x1d6b, 0x0104, "no-such-board"});
#ifdef TLVLINK_TEST_HAVE_LIBUSB
  ASSERT_TRUE(t.ok());
  Status s = t.value()->open();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kTransportUnavailable) << s.error().message();
#else
  ASSERT_FALSE(t.ok());
  EXPECT_NE(std::string(t.error().message()).find("TLVLINK_WITH_USB"), std::string::npos);
#endif
}

}  // namespace
}  // namespace tlvlink::listen
