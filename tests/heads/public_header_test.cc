// Includes only the heads component's umbrella header: compiling proves it is self-contained.
#include "tlvlink/heads.h"

#include <array>

#include <gtest/gtest.h>

TEST(HeadsPublicHeader, UmbrellaIsSelfContained) {
  const std::array<float, 3> v{0.5f, 2.0f, 2.0f};
  EXPECT_EQ(tlvlink::heads::argmax(v), 1);  // the first maximum
}
