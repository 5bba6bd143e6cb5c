// The FunctionFS side as far as it runs without a USB device controller: the descriptor and
// string blobs byte by byte (what the host's libusb code looks for), the transfer rule, and the
// set-up path against a directory of plain files standing in for a functionfs mount. The real
// gadget runs in the emulated board (tools/listen/usb_e2e, not run here).
#include <gtest/gtest.h>

#include <fcntl.h>
#include <linux/aio_abi.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "support/temp_dir.h"
#include "tlvlink/transport/ffs.h"
#include "tlvlink/transport/transport_spec.h"
#include "tlvlink/transport/usb_stream.h"

namespace tlvlink::transport {
namespace {

uint32_t le32(const std::byte* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
         static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
}

TEST(FunctionFs, DescriptorBlobIsV2FullAndHighSpeedBulkPair) {
  std::byte blob[256];
  const size_t n = ffs_descriptors(blob);
  // header (magic, length, flags) + fs_count + hs_count + 2 x (interface 9 + 2 endpoints 7).
  ASSERT_EQ(n, 12u + 8u + 2u * (9u + 7u + 7u));
  EXPECT_EQ(le32(blob), 3u);  // FUNCTIONFS_DESCRIPTORS_MAGIC_V2
  EXPECT_EQ(le32(blob + 4), n);
  EXPECT_EQ(le32(blob + 8), 3u);  // FUNCTIONFS_HAS_FS_DESC | FUNCTIONFS_HAS_HS_DESC
  EXPECT_EQ(le32(blob + 12), 3u);
  EXPECT_EQ(le32(blob + 16), 3u);
  for (int speed = 0; speed < 2; ++speed) {
    const std::byte* d = blob + 20 + speed * 23;
    SCOPED_TRACE(speed == 0 ? "full speed" : "high speed");
    EXPECT_EQ(d[0], std::byte{9});  // bLength
    EXPECT_EQ(d[1], std::byte{4});  // INTERFACE
    EXPECT_EQ(d[4], std::byte{2});  // bNumEndpoints
    EXPECT_EQ(d[5], std::byte{kUsbInterfaceClass});
    EXPECT_EQ(d[6], std::byte{kUsbInterfaceSubclass});
    EXPECT_EQ(d[7], std::byte{kUsbInterfaceProtocol});
    EXPECT_EQ(d[8], std::byte{1});  // iInterface: the first string
    const uint16_t packet = speed == 0 ? kUsbFullSpeedPacket : kUsbHighSpeedPacket;
    const std::byte* in = d + 9;
    const std::byte* out = d + 16;
    EXPECT_EQ(in[1], std::byte{5});  // ENDPOINT
    EXPECT_EQ(in[2], std::byte{0x81});
    EXPECT_EQ(out[2], std::byte{0x02});
    for (const std::byte* ep : {in, out}) {
      EXPECT_EQ(ep[0], std::byte{7});
      EXPECT_EQ(ep[3], std::byte{2});  // bulk
      EXPECT_EQ(
          static_cast<uint16_t>(static_cast<unsigned>(ep[4]) | static_cast<unsigned>(ep[5]) << 8),
          packet);
    }
  }
}

TEST(FunctionFs, StringBlob) {
  std::byte blob[256];
  const size_t n = ffs_strings(blob);
  ASSERT_EQ(n, 16u + 2u + sizeof("tlvlink stream"));
  EXPECT_EQ(le32(blob), 2u);  // FUNCTIONFS_STRINGS_MAGIC
  EXPECT_EQ(le32(blob + 4), n);
  EXPECT_EQ(le32(blob + 8), 1u);
  EXPECT_EQ(le32(blob + 12), 1u);
  EXPECT_EQ(blob[16], std::byte{0x09});
  EXPECT_EQ(blob[17], std::byte{0x04});
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(blob + 18)), "tlvlink stream");
}

TEST(UsbStream, TransfersAlwaysEndShort) {
  for (size_t n : {size_t{1}, size_t{63}, size_t{64}, size_t{512}, size_t{4095}, size_t{16383},
                   size_t{16384}, size_t{100000}}) {
    const size_t chunk = usb_chunk(n);
    const size_t sent = chunk + (usb_needs_pad(chunk) ? 1 : 0);
    EXPECT_LE(sent, kUsbMaxTransfer) << n;
    EXPECT_NE(sent % kUsbPadMultiple, 0u) << n;
    EXPECT_NE(sent % kUsbHighSpeedPacket, 0u) << n;
  }
}

// The transport's I/O is Linux AIO; qemu user mode (the cross stage's ctest) does not implement it.
bool linux_aio_available() {
  aio_context_t ctx = 0;
  if (syscall(SYS_io_setup, 1, &ctx) != 0) return errno != ENOSYS;
  syscall(SYS_io_destroy, ctx);
  return true;
}

TEST(FunctionFs, SetUpWritesDescriptorsThenWaitsForTheHost) {
  if (!linux_aio_available()) {
    GTEST_SKIP() << "Linux AIO (io_setup) is not implemented here (qemu user mode?); the "
                    "FunctionFS transport "
                    "runs against a real gadget in the emulated board (run_tests.sh board)";
  }
  testing::TempDir dir("ffs");
  for (const char* f : {"ep0", "ep1", "ep2"}) std::ofstream(dir / f).put('\0').flush();
  ::truncate((dir / "ep0").c_str(), 0);
  Result<std::unique_ptr<Transport>> t = make_transport("usb:" + dir.path());
  ASSERT_TRUE(t.ok()) << t.error().message();
  Status s = t.value()->open();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kTransportUnavailable);
  EXPECT_NE(std::string(s.error().message()).find("has not enabled"), std::string::npos)
      << s.error().message();
  EXPECT_FALSE(t.value()->peer_present());
  // ep0 received exactly the descriptors, then the strings.
  std::ifstream in(dir / "ep0", std::ios::binary);
  std::vector<char> written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::byte d[256], st[256];
  const size_t nd = ffs_descriptors(d), ns = ffs_strings(st);
  ASSERT_EQ(written.size(), nd + ns);
  EXPECT_EQ(std::memcmp(written.data(), d, nd), 0);
  EXPECT_EQ(std::memcmp(written.data() + nd, st, ns), 0);
}

TEST(FunctionFs, NotMountedIsUnavailableAndSaysWhatToDo) {
  Result<std::unique_ptr<Transport>> t = make_transport("usb:/dev/ffs-tlvlink-absent");
  ASSERT_TRUE(t.ok());
  Status s = t.value()->open();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code(), ErrorCode::kTransportUnavailable);
  EXPECT_NE(std::string(s.error().message()).find("usb_gadget.sh"), std::string::npos)
      << s.error().message();
  EXPECT_FALSE(make_transport("usb,udc=dummy_udc.0").ok()) << "udc without gadget";
}

}  // namespace
}  // namespace tlvlink::transport
