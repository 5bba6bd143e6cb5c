// The umbrella header compiles on its own (no hidden include order) and names the API.
#include "tlvlink/capture/capture.h"

#include <gtest/gtest.h>

TEST(CapturePublicHeader, SelfContained) {
  tlvlink::capture::SourceStats stats;
  tlvlink::capture::FrameAccounting accounting(stats);
  accounting.reset_stream(0);
  EXPECT_EQ(stats.delivered, 0u);
  EXPECT_STREQ(tlvlink::error_code_name(tlvlink::ErrorCode::kCaptureDisconnected),
               "capture.disconnected");
  EXPECT_STREQ(tlvlink::error_code_name(tlvlink::ErrorCode::kCaptureNoDevice), "capture.no_device");
}
