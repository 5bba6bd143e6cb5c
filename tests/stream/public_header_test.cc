// Includes only the stream component's umbrella header: compiling proves it is self-contained.
#include "tlvlink/stream/stream.h"

#include <gtest/gtest.h>

TEST(StreamPublicHeader, UmbrellaIsSelfContained) {
  EXPECT_STREQ(tlvlink::stream::kStageNames[0], "dequeue");
}
