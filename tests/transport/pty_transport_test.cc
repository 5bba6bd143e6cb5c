// The serial and pty transports on real ptys: bytes both ways, hangup seen by both sides, the
// "no reader" state, absent devices, and the link strings of transport_spec.h.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <iterator>
#include <string>

#include "support/temp_dir.h"
#include "tlvlink/transport/pty.h"
#include "tlvlink/transport/serial.h"
#include "tlvlink/transport/transport_spec.h"

namespace tlvlink::transport {
namespace {

// Reads until `want` bytes arrived or ~2 s passed.
std::string read_some(Transport& t, size_t want) {
  std::string got;
  std::byte buf[256];
  for (int i = 0; i < 200 && got.size() < want; ++i) {
    Result<Readiness> r = t.wait(false, 10);
    if (!r.ok() || !r.value().readable) continue;
    Result<size_t> n = t.read(buf);
    if (n.ok()) got.append(reinterpret_cast<const char*>(buf), n.value());
  }
  return got;
}

void write_all(Transport& t, std::string_view s) {
  auto bytes = std::as_bytes(std::span(s.data(), s.size()));
  size_t done = 0;
  for (int i = 0; i < 200 && done < bytes.size(); ++i) {
    Result<Readiness> r = t.wait(true, 10);
    ASSERT_TRUE(r.ok()) << r.error().message();
    if (!r.value().writable) continue;
    Result<size_t> n = t.write(bytes.subspan(done));
    ASSERT_TRUE(n.ok());
    done += n.value();
  }
  ASSERT_EQ(done, bytes.size());
}

TEST(PtyTransport, BytesBothWaysThroughTheLink) {
  testing::TempDir dir("pty");
  PtyTransport board({dir / "tty"});
  ASSERT_TRUE(board.open().ok());
  EXPECT_FALSE(board.peer_present());
  Result<std::unique_ptr<Transport>> host =
      make_serial_transport({dir / "tty", 115200, FlowControl::kNone});
  ASSERT_TRUE(host.ok());
  ASSERT_TRUE(host.value()->open().ok());
  (void)board.wait(false, 0);
  EXPECT_TRUE(board.peer_present());
  write_all(board, std::string("hello\0host", 10));  // raw: the zero byte and no CR/LF mapping
  EXPECT_EQ(read_some(*host.value(), 10), std::string("hello\0host", 10));
  write_all(*host.value(), "\r\nboard\x7f");
  EXPECT_EQ(read_some(board, 8), "\r\nboard\x7f");
}

// Issue 31: a `pty:PATH` naming somebody's file refuses (at make_transport, which --check runs,
// and at open); the file is left byte-identical. A stale link to a pty slave is replaced.
TEST(PtyTransport, NeverReplacesAFileThatIsNotItsLink) {
  testing::TempDir dir("pty");
  const std::string notes = dir / "notes.txt";
  std::ofstream(notes) << "my notes\n";
  Result<std::unique_ptr<Transport>> spec = make_transport("pty:" + notes);
  ASSERT_FALSE(spec.ok());
  EXPECT_EQ(spec.error().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(std::string(spec.error().message()).find(notes + " already exists"), std::string::npos)
      << spec.error().message();
  PtyTransport board({notes});
  Status s = board.open();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(std::string(s.error().message()).find("a regular file"), std::string::npos)
      << s.error().message();
  board.close();
  struct stat st {};
  ASSERT_EQ(::lstat(notes.c_str(), &st), 0);
  EXPECT_TRUE(S_ISREG(st.st_mode));
  std::ifstream in(notes);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "my notes\n");
  // A symlink elsewhere is refused too; one to a pty slave (a killed run's) is taken over.
  const std::string other = dir / "other";
  ASSERT_EQ(::symlink(notes.c_str(), other.c_str()), 0);
  EXPECT_FALSE(PtyTransport({other}).open().ok());
  const std::string stale = dir / "stale";
  ASSERT_EQ(::symlink("/dev/pts/999", stale.c_str()), 0);
  PtyTransport again({stale});
  EXPECT_TRUE(again.open().ok());
}

TEST(PtyTransport, ReaderGoneAndBack) {
  testing::TempDir dir("pty");
  PtyTransport board({dir / "tty"});
  ASSERT_TRUE(board.open().ok());
  auto host = make_serial_transport({dir / "tty", 0, FlowControl::kNone});
  ASSERT_TRUE(host.value()->open().ok());
  (void)board.wait(false, 0);
  ASSERT_TRUE(board.peer_present());
  host.value()->close();
  Result<Readiness> r = board.wait(true, 50);
  ASSERT_TRUE(r.ok()) << "no reader is not an error for the board: it waits";
  EXPECT_FALSE(board.peer_present());
  EXPECT_FALSE(r.value().writable);
  ASSERT_TRUE(host.value()->open().ok());
  (void)board.wait(false, 0);
  EXPECT_TRUE(board.peer_present());
}

TEST(SerialTransport, HangupWhenTheOtherEndCloses) {
  testing::TempDir dir("pty");
  auto board = std::make_unique<PtyTransport>(PtyConfig{dir / "tty"});
  ASSERT_TRUE(board->open().ok());
  auto host = make_serial_transport({dir / "tty", 0, FlowControl::kNone});
  ASSERT_TRUE(host.value()->open().ok());
  board->close();  // the board (or the USB device) went away
  Result<Readiness> r = host.value()->wait(false, 100);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code(), ErrorCode::kTransportDisconnected);
  host.value()->close();
  Status reopen = host.value()->open();
  ASSERT_FALSE(reopen.ok());
  EXPECT_EQ(reopen.error().code(), ErrorCode::kTransportUnavailable) << reopen.error().message();
  EXPECT_EQ(::access((dir / "tty").c_str(), F_OK), -1) << "the board's link is removed with it";
}

TEST(SerialTransport, AbsentDeviceIsUnavailableNotFatal) {
  auto t = make_serial_transport({"/dev/tlvlink-no-such-tty", 921600, FlowControl::kRtsCts});
  ASSERT_TRUE(t.ok());
  Status s = t.value()->open();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kTransportUnavailable);
  EXPECT_NE(std::string(s.error().message()).find("/dev/tlvlink-no-such-tty"), std::string::npos);
}

TEST(SerialTransport, NotATerminal) {
  auto t = make_serial_transport({"/dev/null", 0, FlowControl::kNone});
  Status s = t.value()->open();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kTransport);
  EXPECT_NE(std::string(s.error().message()).find("not a terminal"), std::string::npos)
      << s.error().message();
}

TEST(TransportSpec, ParsesAndNamesWhatIsWrong) {
  EXPECT_TRUE(make_transport("serial:/dev/ttyGS0").ok());
  EXPECT_TRUE(make_transport("serial:/dev/ttyAMA0,baud=921600,flow=rtscts").ok());
  EXPECT_TRUE(make_transport("pty:/tmp/tlvlink-tty").ok());
  struct Bad {
    const char* spec;
    const char* says;
  };
  for (const Bad& b :
       {Bad{"serial:/dev/ttyS0,baud=12345", "not a standard rate"},
        Bad{"serial:/dev/ttyS0,baud=fast", "baud 'fast'"},
        Bad{"serial:/dev/ttyS0,flow=xon", "flow 'xon'"},
        Bad{"serial:/dev/ttyS0,parity=even", "unknown option 'parity'"},
        Bad{"serial:/dev/ttyS0,baud", "not key=value"}, Bad{"serial", "needs a device path"},
        Bad{"carrier-pigeon:/x", "unknown kind 'carrier-pigeon'"}}) {
    Result<std::unique_ptr<Transport>> t = make_transport(b.spec);
    ASSERT_FALSE(t.ok()) << b.spec;
    EXPECT_EQ(t.error().code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(t.error().message()).find(b.says), std::string::npos)
        << t.error().message();
  }
}

}  // namespace
}  // namespace tlvlink::transport
