// The umbrella header must compile on its own (STYLE: public headers are self-contained).
#include "tlvlink/protocol/protocol.h"

#include <gtest/gtest.h>

TEST(ProtocolPublicHeader, SelfContained) {
  EXPECT_EQ(tlvlink::protocol::kHeaderSize, 24u);
  EXPECT_NE(tlvlink::protocol::schema_hash(), 0u);
}
