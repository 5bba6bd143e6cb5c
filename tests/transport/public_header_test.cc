// Includes only the transport component's umbrella header: compiling proves it is
// self-contained.
#include "tlvlink/transport.h"

#include <string>

#include <gtest/gtest.h>

TEST(TransportPublicHeader, UmbrellaIsSelfContained) {
  // An unknown link kind is refused by name, before anything is opened.
  auto t = tlvlink::transport::make_transport("carrier-pigeon:/dev/null");
  ASSERT_FALSE(t.ok());
  EXPECT_NE(std::string(t.error().message()).find("carrier-pigeon"), std::string::npos)
      << t.error().message();
}
