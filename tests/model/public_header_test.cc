// Includes only the public umbrella header: compiling proves it is self-contained.
#include "tlvlink/tlvlink.h"

#include <gtest/gtest.h>

TEST(PublicHeader, UmbrellaIsSelfContained) {
  tlvlink::Status ok;
  EXPECT_TRUE(ok.ok());
  EXPECT_STREQ(tlvlink::error_code_name(tlvlink::ErrorCode::kModelChecksum), "model.checksum");
}
