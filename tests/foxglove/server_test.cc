// The Foxglove server's address parsing and binding (the protocol itself is tested with the real
// client: foxglove.e2e_ws).
#include <gtest/gtest.h>

#include "tlvlink/foxglove/server.h"

namespace tlvlink::foxglove {
namespace {

TEST(FoxgloveServer, ParsesHostAndPort) {
  EXPECT_EQ(parse_host_port("8765")->host, "127.0.0.1");
  EXPECT_EQ(parse_host_port(":9000")->port, 9000);
  EXPECT_EQ(parse_host_port(":9000")->host, "127.0.0.1") << "an empty host is the loopback";
  EXPECT_EQ(parse_host_port("0.0.0.0:1")->host, "0.0.0.0");
  EXPECT_EQ(parse_host_port("[::1]:8765")->host, "::1");
  EXPECT_EQ(parse_host_port("localhost:0")->port, 0);
  for (const char* bad : {"", ":", "host:", "65536", "12a", "-1", "1.5", "host:port"}) {
    auto r = parse_host_port(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(std::string(r.error().message()).find("expected [HOST:]PORT"), std::string::npos)
        << r.error().message();
  }
}

TEST(FoxgloveServer, BindsAFreePortAndRefusesATakenOne) {
  ServerOptions o;
  o.address = {"127.0.0.1", 0};
  auto a = Server::start(o);
  ASSERT_TRUE(a.ok()) << a.error().message();
  const std::string address = a.value()->address();
  EXPECT_EQ(address.rfind("127.0.0.1:", 0), 0u) << address;
  o.address.port = static_cast<uint16_t>(std::stoi(address.substr(10)));
  EXPECT_NE(o.address.port, 0);
  auto b = Server::start(o);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(std::string(b.error().message()).find("cannot serve on " + address), std::string::npos)
      << b.error().message();
  a.value()->shutdown(0);
  EXPECT_EQ(a.value()->counters().clients, 0u);
}

}  // namespace
}  // namespace tlvlink::foxglove
